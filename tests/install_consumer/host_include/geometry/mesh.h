#pragma once
// The host application's own geometry/mesh.h (see core/contact.h beside it).
namespace host {
struct Mesh {
  int triangles = 3;
};
}  // namespace host
