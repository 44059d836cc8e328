#pragma once
// The host application's own core/contact.h. mccd's installed headers must never pick this up
// (they include each other as <mccd/...>); if one did, mccd::Contact would be missing.
namespace host {
struct Contact {
  int id = 7;
};
}  // namespace host
