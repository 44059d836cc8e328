// Mesh files: the reader chosen by extension, and what the writers share.
//
// Readers load the whole file into memory and parse it in place (std::from_chars for text,
// memcpy for binary), so a 100k-triangle mesh loads in a few milliseconds. Every refusal is
// an mccd::Error naming the file, the line (text) or element (binary), and what was expected.
#include <mccd/geometry/mesh_io.h>

#include <filesystem>

#include <mccd/geometry/error.h>

#include <mccd/geometry/mesh_io_detail.h>
#include <mccd/geometry/text_scan.h>

namespace mccd {

TriMesh read_mesh(const std::string& path) {
  const std::string ext = detail::lower(std::filesystem::path(path).extension().string());
  if (ext == ".obj") return read_obj(path);
  if (ext == ".ply") return read_ply(path);
  throw Error(path + ": unknown mesh file type " + detail::quote_tok(ext.empty() ? std::string("(none)") : ext) +
              " (expected .obj or .ply)");
}

namespace detail {

void check_writable_indices(const std::string& path, const TriMesh& mesh) {
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (auto v : mesh.faces[f])
      if (v >= mesh.num_vertices())
        throw Error(path + ": cannot write: face " + std::to_string(f) + ": vertex index " + std::to_string(v) +
                    " out of range [0, " + std::to_string(mesh.num_vertices()) + ")");
}


TriMesh make_mesh(const std::string& path, std::vector<double> xyz, std::vector<Triangle> faces) {
  TriMesh mesh;
  mesh.name = path;
  mesh.vertices = Positions::from_xyz(std::move(xyz));
  mesh.faces = std::move(faces);
  validate_mesh(mesh);
  return mesh;
}

}  // namespace detail
}  // namespace mccd
