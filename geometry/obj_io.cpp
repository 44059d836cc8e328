// Wavefront OBJ: reader and writer.
#include <charconv>
#include <cmath>
#include <limits>

#include <mccd/geometry/error.h>
#include <mccd/geometry/mesh_io.h>

#include <mccd/geometry/atomic_file.h>
#include <mccd/geometry/mesh_io_detail.h>
#include <mccd/geometry/parsers.h>
#include <mccd/geometry/text_scan.h>

namespace mccd {

using namespace detail;

namespace detail {

TriMesh parse_obj(const std::string& path, std::string_view text) {
  if (all_space(text)) throw Error(path + ": empty file");
  std::vector<double> xyz;
  std::vector<Triangle> faces;
  std::vector<std::uint32_t> face_line;  // line of each triangle, for late range errors
  std::vector<std::int64_t> poly;
  LineReader lines(text);
  std::string_view line, tok;
  std::size_t num_v = 0;
  bool any_statement = false;
  auto at = [&](std::size_t line_no) { return path + ": line " + std::to_string(line_no); };
  auto value_name = [](int k) { return k < 3 ? std::string("coordinate ") + "xyz"[k] : "value " + std::to_string(k + 1); };

  while (lines.next(line)) {
    Tokens toks(line);
    if (!toks.next(tok) || tok.front() == '#') continue;
    if (tok == "v") {
      any_statement = true;
      // x y z, then optionally w (a weight: used by rational curves and surfaces only), or
      // r g b (the vertex colours some tools write); those are checked, then ignored.
      double c[3];
      int count = 0;
      std::string_view bad;
      while (toks.next(tok) && tok.front() != '#') {
        double value;
        if (!parse_double(tok, value)) {
          bad = tok;
          break;
        }
        if (!std::isfinite(value))
          throw Error(at(lines.line_no()) + ": " + value_name(count) + " of vertex " + std::to_string(num_v + 1) +
                      " is not finite (" + quote_tok(tok) + ")");
        if (count < 3) c[count] = value;
        ++count;
      }
      if (!bad.empty())
        throw Error(at(lines.line_no()) + ": expected a number for " + value_name(count) + " of vertex " +
                    std::to_string(num_v + 1) + ", got " + quote_tok(bad));
      if (count < 3)
        throw Error(at(lines.line_no()) + ": expected 3 coordinates for vertex " + std::to_string(num_v + 1) +
                    ", got " + std::to_string(count));
      if (count != 3 && count != 4 && count != 6)
        throw Error(at(lines.line_no()) + ": vertex " + std::to_string(num_v + 1) + ": expected x y z, x y z w or " +
                    "x y z r g b, got " + std::to_string(count) + " values");
      xyz.insert(xyz.end(), c, c + 3);
      ++num_v;
    } else if (tok == "f") {
      any_statement = true;
      poly.clear();
      while (toks.next(tok)) {
        if (tok.front() == '#') break;  // a comment after the indices
        const std::size_t slash = tok.find('/');
        const std::string_view num = tok.substr(0, slash);
        std::int64_t idx = 0;
        if (!parse_int(num, idx))
          throw Error(at(lines.line_no()) + ": expected a vertex index (a, a/b, a//c or a/b/c) in face, got " +
                      quote_tok(tok));
        if (idx == 0) throw Error(at(lines.line_no()) + ": vertex index 0 is invalid (OBJ indices start at 1)");
        if (idx < 0) {
          if (static_cast<std::int64_t>(num_v) + idx < 0)
            throw Error(at(lines.line_no()) + ": relative vertex index " + std::to_string(idx) +
                        " points before the first vertex (" + std::to_string(num_v) + " vertices so far)");
          idx = static_cast<std::int64_t>(num_v) + idx;
        } else {
          idx -= 1;
        }
        if (idx > static_cast<std::int64_t>(std::numeric_limits<std::uint32_t>::max() - 1))
          throw Error(at(lines.line_no()) + ": vertex index " + quote_tok(num) + " is too large");
        poly.push_back(idx);
      }
      if (poly.size() < 3)
        throw Error(at(lines.line_no()) + ": face with fewer than 3 vertices (" + std::to_string(poly.size()) + ")");
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
        const Triangle t{static_cast<std::uint32_t>(poly[0]), static_cast<std::uint32_t>(poly[k]),
                         static_cast<std::uint32_t>(poly[k + 1])};
        check_repeated(t, at(lines.line_no()) + ": face");
        faces.push_back(t);
        face_line.push_back(static_cast<std::uint32_t>(lines.line_no()));
      }
    }
    // vt, vn, vp, o, g, s, l, usemtl, mtllib, ...: ignored
  }
  if (!any_statement) throw Error(path + ": no vertices or faces (no 'v' or 'f' lines)");
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (auto v : faces[f])
      if (v >= num_v)
        throw Error(at(face_line[f]) + ": vertex index " + std::to_string(std::uint64_t(v) + 1) +
                    " out of range [1, " + std::to_string(num_v) + "]");
  return make_mesh(path, std::move(xyz), std::move(faces));
}

}  // namespace detail

TriMesh read_obj(const std::string& path) {
  const std::string text = read_all(path);
  return parse_obj(path, text);
}

void write_obj(const std::string& path, const TriMesh& mesh) {
  check_writable_indices(path, mesh);
  std::string out;
  out.reserve(64 + mesh.num_vertices() * 72 + mesh.num_faces() * 24);
  out += "# written by mccd: " + std::to_string(mesh.num_vertices()) + " vertices, " +
         std::to_string(mesh.num_faces()) + " triangles\n";
  char buf[64];
  for (std::size_t v = 0; v < mesh.vertices.rows(); ++v) {
    out += 'v';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      // same text as printf("%.17g"): enough digits to round-trip every double
      auto [p, ec] = std::to_chars(buf, buf + sizeof buf, mesh.vertices(v, k), std::chars_format::general, 17);
      out.append(buf, p);
    }
    out += '\n';
  }
  for (const Triangle& t : mesh.faces) {
    out += 'f';
    for (auto v : t) {
      out += ' ';
      out += std::to_string(std::uint64_t(v) + 1);
    }
    out += '\n';
  }
  write_atomically(path, out);
}

}  // namespace mccd
