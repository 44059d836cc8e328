// PLY: reader (ascii, binary little- and big-endian) and writer (binary little-endian).
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include <mccd/geometry/error.h>
#include <mccd/geometry/large_allocator.h>
#include <mccd/geometry/mesh_io.h>

#include <mccd/geometry/atomic_file.h>
#include <mccd/geometry/mesh_io_detail.h>
#include <mccd/geometry/parsers.h>
#include <mccd/geometry/ply_format.h>
#include <mccd/geometry/text_scan.h>

namespace mccd {

using namespace detail;

namespace {

/// Collects the triangles of one polygon of `n` indices (fan), checking range and repeats.
class FaceBuilder {
 public:
  FaceBuilder(std::uint64_t num_vertices, std::vector<Triangle>& out) : nv_(num_vertices), out_(out) {}
  /// `where` prefix is built lazily, only for errors.
  template <class Where>
  void add(const std::int64_t* idx, std::size_t n, std::uint64_t face, Where&& where) {
    if (n < 3)
      throw Error(where() + "face " + std::to_string(face) + ": expected at least 3 vertex indices, got " +
                  std::to_string(n));
    for (std::size_t k = 0; k < n; ++k)
      if (idx[k] < 0 || static_cast<std::uint64_t>(idx[k]) >= nv_)
        throw Error(where() + "face " + std::to_string(face) + ": vertex index " + std::to_string(idx[k]) +
                    " out of range [0, " + std::to_string(nv_) + ")");
    for (std::size_t k = 1; k + 1 < n; ++k) {
      const Triangle t{static_cast<std::uint32_t>(idx[0]), static_cast<std::uint32_t>(idx[k]),
                       static_cast<std::uint32_t>(idx[k + 1])};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) check_repeated(t, where() + "face " + std::to_string(face));
      out_.push_back(t);
    }
  }

 private:
  std::uint64_t nv_;
  std::vector<Triangle>& out_;
};

void parse_ply_ascii(const std::string& path, std::string_view data, std::size_t first_line, const Header& h,
                     const Layout& L, std::vector<double>& xyz, std::vector<Triangle>& faces) {
  LineReader lines(data, first_line);
  std::string_view line, tok;
  const std::uint64_t nv = h.elements[L.vertex_elem].count;
  FaceBuilder builder(nv, faces);
  std::vector<std::int64_t> idx;
  auto where = [&] { return path + ": line " + std::to_string(lines.line_no()) + ": "; };

  for (std::size_t ei = 0; ei < h.elements.size(); ++ei) {
    const Element& e = h.elements[ei];
    const bool is_vertex = static_cast<int>(ei) == L.vertex_elem;
    const bool is_face = static_cast<int>(ei) == L.face_elem;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      // next non-blank line
      bool got = false;
      while (lines.next(line))
        if (!all_space(line)) {
          got = true;
          break;
        }
      if (!got)
        throw Error(path + ": line " + std::to_string(lines.line_no() + 1) + ": expected " + e.name + " " +
                    std::to_string(i) + " of " + std::to_string(e.count) + ", reached the end of the file");
      Tokens toks(line);
      double c[3] = {0, 0, 0};
      for (std::size_t p = 0; p < e.props.size(); ++p) {
        const Property& prop = e.props[p];
        if (prop.is_list) {
          std::int64_t n = 0;
          if (!toks.next(tok))
            throw Error(where() + "expected the item count of list '" + prop.name + "' of " + e.name + " " +
                        std::to_string(i) + ", got the end of the line");
          if (!parse_int(tok, n) || n < 0)
            throw Error(where() + "expected an item count for list '" + prop.name + "' of " + e.name + " " +
                        std::to_string(i) + ", got " + quote_tok(tok));
          const bool want = is_face && static_cast<int>(p) == L.indices;
          if (want) idx.clear();
          for (std::int64_t k = 0; k < n; ++k) {
            if (!toks.next(tok))
              throw Error(where() + "list '" + prop.name + "' of " + e.name + " " + std::to_string(i) + ": expected " +
                          std::to_string(n) + " items, got " + std::to_string(k));
            if (want) {
              std::int64_t v = 0;
              if (!parse_int(tok, v))
                throw Error(where() + "expected an integer in list '" + prop.name + "' of " + e.name + " " +
                            std::to_string(i) + ", got " + quote_tok(tok));
              idx.push_back(v);
            } else {
              double d;
              if (!parse_double(tok, d))
                throw Error(where() + "expected a number in list '" + prop.name + "' of " + e.name + " " +
                            std::to_string(i) + ", got " + quote_tok(tok));
            }
          }
          if (want) builder.add(idx.data(), idx.size(), i, where);
        } else {
          if (!toks.next(tok))
            throw Error(where() + "expected a number for property '" + prop.name + "' of " + e.name + " " +
                        std::to_string(i) + ", got the end of the line");
          double d;
          if (!parse_double(tok, d))
            throw Error(where() + "expected a number for property '" + prop.name + "' of " + e.name + " " +
                        std::to_string(i) + ", got " + quote_tok(tok));
          if (is_vertex)
            for (int k = 0; k < 3; ++k)
              if (static_cast<int>(p) == L.xyz[k]) {
                if (!std::isfinite(d))
                  throw Error(where() + "coordinate " + "xyz"[k] + " of vertex " + std::to_string(i) +
                              " is not finite (" + quote_tok(tok) + ")");
                c[k] = d;
              }
        }
      }
      const std::string_view extra = toks.rest();
      if (!extra.empty())
        throw Error(where() + e.name + " " + std::to_string(i) + ": unexpected extra value " + quote_tok(extra) +
                    " (the header declares " + std::to_string(e.props.size()) + " properties)");
      if (is_vertex) xyz.insert(xyz.end(), c, c + 3);
    }
  }
  while (lines.next(line))
    if (!all_space(line))
      throw Error(where() + "unexpected data after the last element (" + quote_tok(line) +
                  "): the element counts in the header are wrong");
}

void parse_ply_binary(const std::string& path, std::string_view data, bool swap, const Header& h, const Layout& L,
                      std::vector<double>& xyz, std::vector<Triangle>& faces) {
  const char* p = data.data();
  const char* const end = data.data() + data.size();
  const std::uint64_t nv = h.elements[L.vertex_elem].count;
  FaceBuilder builder(nv, faces);
  std::vector<std::int64_t> idx;
  auto truncated = [&](const Element& e, std::uint64_t i) {
    return Error(path + ": truncated binary data: " + e.name + " " + std::to_string(i) + " of " +
                 std::to_string(e.count));
  };

  for (std::size_t ei = 0; ei < h.elements.size(); ++ei) {
    const Element& e = h.elements[ei];
    const bool is_vertex = static_cast<int>(ei) == L.vertex_elem;
    const bool is_face = static_cast<int>(ei) == L.face_elem;
    // Fixed-size elements (no lists): one stride, checked once.
    bool fixed = true;
    std::size_t stride = 0;
    std::vector<std::size_t> offset(e.props.size());
    for (std::size_t k = 0; k < e.props.size(); ++k) {
      if (e.props[k].is_list) fixed = false;
      offset[k] = stride;
      stride += scalar_size(e.props[k].type);
    }
    if (fixed) {
      const auto avail = static_cast<std::uint64_t>(end - p);
      if (stride > 0 && avail / stride < e.count) throw truncated(e, avail / stride);
      if (is_vertex) {
        const std::size_t o[3] = {offset[L.xyz[0]], offset[L.xyz[1]], offset[L.xyz[2]]};
        const Scalar t[3] = {e.props[L.xyz[0]].type, e.props[L.xyz[1]].type, e.props[L.xyz[2]].type};
        xyz.reserve(3 * e.count);
        populate_pages(xyz.data(), 3 * e.count * sizeof(double));  // about to be written in full
        xyz.resize(3 * e.count);
        double* out = xyz.data();
        if (t[0] == Scalar::Float32 && t[1] == Scalar::Float32 && t[2] == Scalar::Float32) {
          for (std::uint64_t i = 0; i < e.count; ++i, p += stride, out += 3)
            for (int k = 0; k < 3; ++k) out[k] = load<float>(p + o[k], swap);
        } else if (t[0] == Scalar::Float64 && t[1] == Scalar::Float64 && t[2] == Scalar::Float64) {
          for (std::uint64_t i = 0; i < e.count; ++i, p += stride, out += 3)
            for (int k = 0; k < 3; ++k) out[k] = load<double>(p + o[k], swap);
        } else {
          for (std::uint64_t i = 0; i < e.count; ++i, p += stride, out += 3)
            for (int k = 0; k < 3; ++k) out[k] = load_double(p + o[k], t[k], swap);
        }
      } else {
        p += stride * e.count;
      }
      continue;
    }
    if (is_face) {
      faces.reserve(std::min<std::uint64_t>(e.count, static_cast<std::uint64_t>(end - p) / 4));
      populate_pages(faces.data(), faces.capacity() * sizeof(Triangle));  // about to be written
    }
    if (is_vertex) xyz.reserve(std::min<std::uint64_t>(3 * e.count, static_cast<std::uint64_t>(end - p)));
    for (std::uint64_t i = 0; i < e.count; ++i) {
      double c[3] = {0, 0, 0};
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const Property& prop = e.props[k];
        if (!prop.is_list) {
          const std::size_t s = scalar_size(prop.type);
          if (static_cast<std::size_t>(end - p) < s) throw truncated(e, i);
          if (is_vertex)
            for (int j = 0; j < 3; ++j)
              if (static_cast<int>(k) == L.xyz[j]) c[j] = load_double(p, prop.type, swap);
          p += s;
          continue;
        }
        const std::size_t cs = scalar_size(prop.count_type);
        if (static_cast<std::size_t>(end - p) < cs) throw truncated(e, i);
        const std::int64_t n = load_int(p, prop.count_type, swap);
        p += cs;
        if (n < 0)
          throw Error(path + ": " + e.name + " " + std::to_string(i) + ": negative item count " + std::to_string(n) +
                      " for list '" + prop.name + "'");
        const std::size_t is = scalar_size(prop.type);
        if (static_cast<std::uint64_t>(end - p) / is < static_cast<std::uint64_t>(n)) throw truncated(e, i);
        if (is_face && static_cast<int>(k) == L.indices) {
          idx.resize(static_cast<std::size_t>(n));
          if (prop.type == Scalar::Int32 || prop.type == Scalar::UInt32) {
            const bool sign = prop.type == Scalar::Int32;
            for (std::int64_t j = 0; j < n; ++j, p += 4)
              idx[j] = sign ? std::int64_t(load<std::int32_t>(p, swap)) : std::int64_t(load<std::uint32_t>(p, swap));
          } else {
            for (std::int64_t j = 0; j < n; ++j, p += is) idx[j] = load_int(p, prop.type, swap);
          }
          builder.add(idx.data(), idx.size(), i, [&] { return path + ": "; });
        } else {
          p += is * static_cast<std::size_t>(n);
        }
      }
      if (is_vertex) xyz.insert(xyz.end(), c, c + 3);
    }
  }
  const std::string_view rest(p, static_cast<std::size_t>(end - p));
  if (!all_space(rest))
    throw Error(path + ": " + std::to_string(rest.size()) +
                " bytes of unexpected data after the last element: the element counts in the header are wrong");
}

}  // namespace

namespace detail {

TriMesh parse_ply(const std::string& path, std::string_view text) {
  if (all_space(text)) throw Error(path + ": empty file");
  const Header h = parse_ply_header(path, text);
  const Layout L = make_layout(path, h);
  const std::string_view data = text.substr(h.data_offset);
  const std::uint64_t nv = h.elements[L.vertex_elem].count;
  std::vector<double> xyz;
  std::vector<Triangle> faces;
  if (h.format == Format::Ascii) {
    xyz.reserve(std::min<std::uint64_t>(3 * nv, data.size()));
    parse_ply_ascii(path, data, h.data_line, h, L, xyz, faces);
  } else {
    const bool file_big = h.format == Format::BinaryBE;
    const bool host_big = std::endian::native == std::endian::big;
    parse_ply_binary(path, data, file_big != host_big, h, L, xyz, faces);
  }
  return make_mesh(path, std::move(xyz), std::move(faces));
}

}  // namespace detail

namespace {

template <class T>
void put(std::string& out, T v) {
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    char tmp[sizeof(T)];
    std::memcpy(tmp, &v, sizeof(T));
    std::reverse(tmp, tmp + sizeof(T));
    out.append(tmp, sizeof(T));
  } else {
    char tmp[sizeof(T)];
    std::memcpy(tmp, &v, sizeof(T));
    out.append(tmp, sizeof(T));
  }
}


}  // namespace

TriMesh read_ply(const std::string& path) {
  const std::string text = read_all(path);
  return parse_ply(path, text);
}

void write_ply(const std::string& path, const TriMesh& mesh, const FaceColors& colors) {
  if (!colors.empty() && colors.size() != mesh.num_faces())
    throw Error(path + ": cannot write: " + std::to_string(colors.size()) + " face colours for " +
                std::to_string(mesh.num_faces()) + " faces");
  check_writable_indices(path, mesh);
  if (mesh.num_vertices() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw Error(path + ": cannot write: too many vertices for int indices");
  std::string out;
  out.reserve(256 + mesh.num_vertices() * 24 + mesh.num_faces() * (13 + (colors.empty() ? 0 : 3)));
  out += "ply\nformat binary_little_endian 1.0\ncomment written by mccd\n";
  out += "element vertex " + std::to_string(mesh.num_vertices()) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  out += "element face " + std::to_string(mesh.num_faces()) + "\n";
  out += "property list uchar int vertex_indices\n";
  if (!colors.empty()) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out += "end_header\n";
  for (std::size_t v = 0; v < mesh.vertices.rows(); ++v)
    for (int k = 0; k < 3; ++k) put<double>(out, mesh.vertices(v, k));
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    put<std::uint8_t>(out, 3);
    for (auto v : mesh.faces[f]) put<std::int32_t>(out, static_cast<std::int32_t>(v));
    if (!colors.empty())
      for (auto c : colors[f]) put<std::uint8_t>(out, c);
  }
  write_atomically(path, out);
}

}  // namespace mccd
