// Mesh files: OBJ and PLY readers and writers, and frame sequences.
//
// Readers load the whole file into memory and parse it in place (std::from_chars for text,
// memcpy for binary), so a 100k-triangle mesh loads in a few milliseconds. Every refusal is
// an mccd::Error naming the file, the line (text) or element (binary), and what was expected.
#include "geometry/mesh_io.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string_view>
#include <system_error>

#include "geometry/error.h"

namespace mccd {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Small helpers
// ---------------------------------------------------------------------------------------------

std::string quote_tok(std::string_view s) {
  constexpr std::size_t kMax = 40;
  std::string out = "'";
  if (s.size() > kMax) {
    out.append(s.substr(0, kMax));
    out += "...";
  } else {
    out.append(s);
  }
  out += "'";
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// Whole file as bytes. Throws "cannot open" naming the file and the reason.
std::string read_all(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw Error(path + ": cannot open: is a directory");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error(path + ": cannot open: " + std::strerror(errno));
  std::string data;
  char buf[1 << 16];
  if (std::fseek(f, 0, SEEK_END) == 0) {
    const long size = std::ftell(f);
    if (size > 0) data.reserve(static_cast<std::size_t>(size));
    std::fseek(f, 0, SEEK_SET);
  }
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) data.append(buf, n);
  const bool failed = std::ferror(f) != 0;
  const int err = errno;
  std::fclose(f);
  if (failed) throw Error(path + ": cannot read: " + std::strerror(err));
  return data;
}

bool all_space(std::string_view s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return is_space(c) || c == '\n' || c == '\0'; });
}

/// Splits text into lines, tracking line numbers (1-based); strips a trailing '\r'.
class LineReader {
 public:
  LineReader(std::string_view text, std::size_t first_line = 1) : text_(text), next_line_(first_line) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line = text_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end == std::string_view::npos ? text_.size() : end + 1;
    line_no_ = next_line_++;
    return true;
  }
  std::size_t line_no() const { return line_no_; }
  std::size_t offset() const { return pos_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t next_line_;
  std::size_t line_no_ = 0;
};

/// Whitespace-separated tokens of one line.
class Tokens {
 public:
  explicit Tokens(std::string_view line) : s_(line) {}
  bool next(std::string_view& tok) {
    while (pos_ < s_.size() && is_space(s_[pos_])) ++pos_;
    if (pos_ >= s_.size()) return false;
    const std::size_t start = pos_;
    while (pos_ < s_.size() && !is_space(s_[pos_])) ++pos_;
    tok = s_.substr(start, pos_ - start);
    return true;
  }
  std::string_view rest() {
    while (pos_ < s_.size() && is_space(s_[pos_])) ++pos_;
    return s_.substr(pos_);
  }

 private:
  std::string_view s_;
  std::size_t pos_ = 0;
};

/// A whole token as a number (an optional leading '+' allowed); false on anything else.
template <class T>
bool parse_number(std::string_view tok, T& out) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  auto [p, ec] = std::from_chars(b, e, out);
  return ec == std::errc() && p == e;
}
bool parse_double(std::string_view tok, double& out) { return parse_number(tok, out); }
bool parse_int(std::string_view tok, std::int64_t& out) { return parse_number(tok, out); }

void check_repeated(const Triangle& t, const std::string& where) {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
    throw Error(where + ": repeated vertex index (" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " +
                std::to_string(t[2]) + ")");
}

Positions to_positions(const std::vector<double>& xyz) {
  Positions p(static_cast<Eigen::Index>(xyz.size() / 3), 3);
  if (!xyz.empty()) std::memcpy(p.data(), xyz.data(), xyz.size() * sizeof(double));
  return p;
}

// ---------------------------------------------------------------------------------------------
// OBJ
// ---------------------------------------------------------------------------------------------

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

  while (lines.next(line)) {
    Tokens toks(line);
    if (!toks.next(tok) || tok.front() == '#') continue;
    if (tok == "v") {
      any_statement = true;
      double c[3];
      for (int k = 0; k < 3; ++k) {
        if (!toks.next(tok))
          throw Error(at(lines.line_no()) + ": expected 3 coordinates for vertex " + std::to_string(num_v + 1) +
                      ", got " + std::to_string(k));
        if (!parse_double(tok, c[k]))
          throw Error(at(lines.line_no()) + ": expected a number for coordinate " + "xyz"[k] + " of vertex " +
                      std::to_string(num_v + 1) + ", got " + quote_tok(tok));
        if (!std::isfinite(c[k]))
          throw Error(at(lines.line_no()) + ": coordinate " + "xyz"[k] + " of vertex " + std::to_string(num_v + 1) +
                      " is not finite (" + std::string(tok) + ")");
      }
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
          throw Error(at(lines.line_no()) + ": vertex index " + std::string(num) + " is too large");
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
  TriMesh mesh;
  mesh.name = path;
  mesh.vertices = to_positions(xyz);
  mesh.faces = std::move(faces);
  validate_mesh(mesh);
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// PLY
// ---------------------------------------------------------------------------------------------

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool scalar_from_name(std::string_view n, Scalar& s) {
  static const std::pair<std::string_view, Scalar> table[] = {
      {"char", Scalar::Int8},     {"int8", Scalar::Int8},       {"uchar", Scalar::UInt8},
      {"uint8", Scalar::UInt8},   {"short", Scalar::Int16},     {"int16", Scalar::Int16},
      {"ushort", Scalar::UInt16}, {"uint16", Scalar::UInt16},   {"int", Scalar::Int32},
      {"int32", Scalar::Int32},   {"uint", Scalar::UInt32},     {"uint32", Scalar::UInt32},
      {"float", Scalar::Float32}, {"float32", Scalar::Float32}, {"double", Scalar::Float64},
      {"float64", Scalar::Float64}};
  for (auto& [name, type] : table)
    if (n == name) {
      s = type;
      return true;
    }
  return false;
}

std::size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::Int8:
    case Scalar::UInt8:
      return 1;
    case Scalar::Int16:
    case Scalar::UInt16:
      return 2;
    case Scalar::Int32:
    case Scalar::UInt32:
    case Scalar::Float32:
      return 4;
    case Scalar::Float64:
      return 8;
  }
  return 0;
}

bool is_integer(Scalar s) { return s != Scalar::Float32 && s != Scalar::Float64; }

template <class T>
T load(const char* p, bool swap) {
  T v;
  if (swap) {
    char tmp[sizeof(T)];
    for (std::size_t i = 0; i < sizeof(T); ++i) tmp[i] = p[sizeof(T) - 1 - i];
    std::memcpy(&v, tmp, sizeof(T));
  } else {
    std::memcpy(&v, p, sizeof(T));
  }
  return v;
}

/// The scalar of type `s` at `p`, converted to R. List counts and indices are integer types
/// (checked in the header), so R = std::int64_t never sees a float.
template <class R>
R load_as(const char* p, Scalar s, bool swap) {
  switch (s) {
    case Scalar::Int8: return static_cast<R>(load<std::int8_t>(p, false));
    case Scalar::UInt8: return static_cast<R>(load<std::uint8_t>(p, false));
    case Scalar::Int16: return static_cast<R>(load<std::int16_t>(p, swap));
    case Scalar::UInt16: return static_cast<R>(load<std::uint16_t>(p, swap));
    case Scalar::Int32: return static_cast<R>(load<std::int32_t>(p, swap));
    case Scalar::UInt32: return static_cast<R>(load<std::uint32_t>(p, swap));
    case Scalar::Float32: return static_cast<R>(load<float>(p, swap));
    case Scalar::Float64: return static_cast<R>(load<double>(p, swap));
  }
  return 0;
}
double load_double(const char* p, Scalar s, bool swap) { return load_as<double>(p, s, swap); }
std::int64_t load_int(const char* p, Scalar s, bool swap) { return load_as<std::int64_t>(p, s, swap); }

struct Property {
  std::string name;
  bool is_list = false;
  Scalar count_type = Scalar::UInt8;  // lists only
  Scalar type = Scalar::Float32;      // the value type (of the items, for lists)
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
  std::size_t header_line = 0;
};

enum class Format { Ascii, BinaryLE, BinaryBE };

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t data_offset = 0;  // first byte after "end_header\n"
  std::size_t data_line = 0;    // line number of the first data line (ascii)
};

Header parse_ply_header(const std::string& path, std::string_view text) {
  Header h;
  LineReader lines(text);
  std::string_view line, tok;
  auto at = [&] { return path + ": line " + std::to_string(lines.line_no()) + ": "; };
  if (!lines.next(line) || line != "ply")
    throw Error(path + ": header: not a PLY file (the first line must be 'ply')");
  bool have_format = false, ended = false;
  while (lines.next(line)) {
    Tokens toks(line);
    if (!toks.next(tok)) continue;
    if (tok == "comment" || tok == "obj_info") continue;
    if (tok == "end_header") {
      ended = true;
      break;
    }
    if (tok == "format") {
      std::string_view fmt;
      if (!toks.next(fmt)) throw Error(at() + "header: 'format' needs a value");
      if (fmt == "ascii") h.format = Format::Ascii;
      else if (fmt == "binary_little_endian") h.format = Format::BinaryLE;
      else if (fmt == "binary_big_endian") h.format = Format::BinaryBE;
      else
        throw Error(at() + "header: unknown format " + quote_tok(fmt) +
                    " (expected ascii, binary_little_endian or binary_big_endian)");
      have_format = true;
    } else if (tok == "element") {
      Element e;
      std::string_view name, count;
      if (!toks.next(name) || !toks.next(count))
        throw Error(at() + "header: expected 'element NAME COUNT'");
      std::int64_t n = 0;
      if (!parse_int(count, n) || n < 0)
        throw Error(at() + "header: expected a non-negative element count for " + quote_tok(name) + ", got " +
                    quote_tok(count));
      e.name = std::string(name);
      e.count = static_cast<std::uint64_t>(n);
      e.header_line = lines.line_no();
      for (const Element& other : h.elements)
        if (other.name == e.name) throw Error(at() + "header: duplicate element " + quote_tok(name));
      h.elements.push_back(std::move(e));
    } else if (tok == "property") {
      if (h.elements.empty()) throw Error(at() + "header: property before any element");
      Property p;
      std::string_view type;
      if (!toks.next(type)) throw Error(at() + "header: expected 'property TYPE NAME'");
      if (type == "list") {
        std::string_view ct, it;
        if (!toks.next(ct) || !toks.next(it))
          throw Error(at() + "header: expected 'property list COUNT_TYPE ITEM_TYPE NAME'");
        p.is_list = true;
        if (!scalar_from_name(ct, p.count_type)) throw Error(at() + "header: unknown property type " + quote_tok(ct));
        if (!scalar_from_name(it, p.type)) throw Error(at() + "header: unknown property type " + quote_tok(it));
        if (!is_integer(p.count_type))
          throw Error(at() + "header: the count type of a list must be an integer type, got " + quote_tok(ct));
      } else if (!scalar_from_name(type, p.type)) {
        throw Error(at() + "header: unknown property type " + quote_tok(type));
      }
      std::string_view name;
      if (!toks.next(name)) throw Error(at() + "header: property without a name");
      p.name = std::string(name);
      h.elements.back().props.push_back(std::move(p));
    } else {
      throw Error(at() + "header: unknown keyword " + quote_tok(tok));
    }
  }
  if (!ended) throw Error(path + ": header: missing 'end_header'");
  if (!have_format) throw Error(path + ": header: missing 'format' line");
  h.data_offset = lines.offset();
  h.data_line = lines.line_no() + 1;
  return h;
}

/// Where the reader finds what it needs in the elements.
struct Layout {
  int vertex_elem = -1, face_elem = -1;
  int xyz[3] = {-1, -1, -1};  // property indices in the vertex element
  int indices = -1;           // property index of vertex_indices in the face element
};

Layout make_layout(const std::string& path, const Header& h) {
  Layout L;
  for (std::size_t i = 0; i < h.elements.size(); ++i) {
    if (h.elements[i].name == "vertex") L.vertex_elem = static_cast<int>(i);
    if (h.elements[i].name == "face") L.face_elem = static_cast<int>(i);
  }
  if (L.vertex_elem < 0) throw Error(path + ": header: no 'vertex' element");
  const Element& ve = h.elements[L.vertex_elem];
  for (std::size_t p = 0; p < ve.props.size(); ++p)
    for (int k = 0; k < 3; ++k)
      if (ve.props[p].name == std::string(1, "xyz"[k])) {
        if (ve.props[p].is_list)
          throw Error(path + ": line " + std::to_string(ve.header_line) + ": header: vertex property '" +
                      ve.props[p].name + "' must be a scalar, not a list");
        L.xyz[k] = static_cast<int>(p);
      }
  for (int k = 0; k < 3; ++k)
    if (L.xyz[k] < 0) throw Error(path + ": header: element 'vertex' has no property '" + "xyz"[k] + "'");
  if (ve.count > std::numeric_limits<std::uint32_t>::max())
    throw Error(path + ": header: too many vertices (" + std::to_string(ve.count) + ")");
  if (L.face_elem >= 0) {
    const Element& fe = h.elements[L.face_elem];
    for (std::size_t p = 0; p < fe.props.size(); ++p)
      if (fe.props[p].name == "vertex_indices" || fe.props[p].name == "vertex_index") {
        if (!fe.props[p].is_list)
          throw Error(path + ": header: face property '" + fe.props[p].name + "' must be a list");
        if (!is_integer(fe.props[p].type))
          throw Error(path + ": header: face property '" + fe.props[p].name + "' must hold integers");
        L.indices = static_cast<int>(p);
        break;
      }
    if (L.indices < 0) throw Error(path + ": header: element 'face' has no list property 'vertex_indices'");
  }
  return L;
}

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
                              " is not finite (" + std::string(tok) + ")");
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
    if (is_face) faces.reserve(std::min<std::uint64_t>(e.count, static_cast<std::uint64_t>(end - p) / 4));
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
  TriMesh mesh;
  mesh.name = path;
  mesh.vertices = to_positions(xyz);
  mesh.faces = std::move(faces);
  validate_mesh(mesh);
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// Writers
// ---------------------------------------------------------------------------------------------

/// Writes `bytes` to a temporary beside `path`, then renames it over `path`. On any failure
/// the temporary is removed and nothing is left at `path` that was not there before.
void write_atomically(const std::string& path, const std::string& bytes) {
  static std::atomic<unsigned> counter{0};
  const fs::path target(path);
  std::string tmp_name(1, '.');
  tmp_name += target.filename().string();
  tmp_name += ".tmp";
  tmp_name += std::to_string(::getpid());
  tmp_name += '_';
  tmp_name += std::to_string(counter++);
  fs::path tmp = target;
  tmp.replace_filename(tmp_name);
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw Error(path + ": cannot write: " + std::strerror(errno));
  const bool wrote = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  int err = errno;
  const bool closed = std::fclose(f) == 0;
  if (!closed && wrote) err = errno;
  std::error_code ec;
  if (!wrote || !closed) {
    fs::remove(tmp, ec);
    throw Error(path + ": cannot write: " + std::strerror(err));
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(path + ": cannot write: " + ec.message());
  }
}

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

void check_writable_indices(const std::string& path, const TriMesh& mesh) {
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (auto v : mesh.faces[f])
      if (v >= mesh.num_vertices())
        throw Error(path + ": cannot write: face " + std::to_string(f) + ": vertex index " + std::to_string(v) +
                    " out of range [0, " + std::to_string(mesh.num_vertices()) + ")");
}

/// printf("%d")-style field of a frame pattern.
struct PatternField {
  std::string prefix, suffix;
  bool zero_pad = false;
  int width = 0;
};

PatternField parse_pattern(const std::string& pattern) {
  PatternField pf;
  bool found = false;
  std::string* cur = &pf.prefix;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      *cur += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      *cur += '%';
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    bool zero = false;
    if (j < pattern.size() && pattern[j] == '0') {
      zero = true;
      ++j;
    }
    int width = 0;
    while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])) && width < 100)
      width = width * 10 + (pattern[j++] - '0');
    if (found || j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'i' && pattern[j] != 'u') || width > 32)
      throw Error("frame pattern '" + pattern + "': expected exactly one %d-style field (as in frame%03d.ply)");
    found = true;
    pf.zero_pad = zero;
    pf.width = width;
    cur = &pf.suffix;
    i = j;
  }
  if (!found) throw Error("frame pattern '" + pattern + "': expected exactly one %d-style field (as in frame%03d.ply)");
  return pf;
}

std::string format_frame(const PatternField& pf, std::size_t i) {
  std::string num = std::to_string(i);
  if (static_cast<int>(num.size()) < pf.width) num.insert(0, pf.width - num.size(), pf.zero_pad ? '0' : ' ');
  return pf.prefix + num + pf.suffix;
}

std::string face_str(const Triangle& t) {
  return "(" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")";
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Public API
// ---------------------------------------------------------------------------------------------

TriMesh read_obj(const std::string& path) {
  const std::string text = read_all(path);
  return parse_obj(path, text);
}

TriMesh read_ply(const std::string& path) {
  const std::string text = read_all(path);
  return parse_ply(path, text);
}

TriMesh read_mesh(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext == ".obj") return read_obj(path);
  if (ext == ".ply") return read_ply(path);
  throw Error(path + ": unknown mesh file type " + quote_tok(ext.empty() ? std::string("(none)") : ext) +
              " (expected .obj or .ply)");
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
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v)
    for (int k = 0; k < 3; ++k) put<double>(out, mesh.vertices(v, k));
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    put<std::uint8_t>(out, 3);
    for (auto v : mesh.faces[f]) put<std::int32_t>(out, static_cast<std::int32_t>(v));
    if (!colors.empty())
      for (auto c : colors[f]) put<std::uint8_t>(out, c);
  }
  write_atomically(path, out);
}

void write_obj(const std::string& path, const TriMesh& mesh) {
  check_writable_indices(path, mesh);
  std::string out;
  out.reserve(64 + mesh.num_vertices() * 72 + mesh.num_faces() * 24);
  out += "# written by mccd: " + std::to_string(mesh.num_vertices()) + " vertices, " +
         std::to_string(mesh.num_faces()) + " triangles\n";
  char buf[64];
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
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

std::vector<std::string> expand_frame_pattern(const std::string& pattern) {
  if (pattern.find('%') == std::string::npos) return {pattern};
  const PatternField pf = parse_pattern(pattern);
  std::error_code ec;
  std::size_t i = 0;
  if (!fs::exists(format_frame(pf, 0), ec)) i = 1;
  std::vector<std::string> out;
  for (;; ++i) {
    std::string name = format_frame(pf, i);
    if (!fs::exists(name, ec)) break;
    out.push_back(std::move(name));
  }
  if (out.empty())
    throw Error("frame pattern '" + pattern + "': no file found (tried '" + format_frame(pf, 0) + "' and '" +
                format_frame(pf, 1) + "')");
  return out;
}

std::vector<std::string> frame_paths(const std::vector<std::string>& paths_or_pattern) {
  std::vector<std::string> paths;
  if (paths_or_pattern.size() == 1 && paths_or_pattern[0].find('%') != std::string::npos)
    paths = expand_frame_pattern(paths_or_pattern[0]);
  else
    paths = paths_or_pattern;
  if (paths.empty()) throw Error("read_frames: no frame files given");
  return paths;
}

Positions read_frame(const std::string& path, std::size_t index, const TriMesh& first, const std::string& first_path) {
  TriMesh m = read_mesh(path);
  const std::string what = path + " (frame " + std::to_string(index) + ")";
  if (m.num_vertices() != first.num_vertices())
    throw Error(what + ": has " + std::to_string(m.num_vertices()) + " vertices, expected " +
                std::to_string(first.num_vertices()) + " as in " + first_path);
  const std::size_t n = std::min(m.num_faces(), first.num_faces());
  for (std::size_t f = 0; f < n; ++f)
    if (m.faces[f] != first.faces[f])
      throw Error(what + ": face " + std::to_string(f) + " is " + face_str(m.faces[f]) + ", expected " +
                  face_str(first.faces[f]) + " as in " + first_path);
  if (m.num_faces() != first.num_faces())
    throw Error(what + ": has " + std::to_string(m.num_faces()) + " triangles, expected " +
                std::to_string(first.num_faces()) + " as in " + first_path + " (first differing face " +
                std::to_string(n) + ")");
  return std::move(m.vertices);
}

FrameSequence read_frames(const std::vector<std::string>& paths_or_pattern) {
  const std::vector<std::string> paths = frame_paths(paths_or_pattern);
  FrameSequence seq;
  seq.frames.reserve(paths.size());
  seq.mesh = read_mesh(paths[0]);
  seq.frames.push_back(seq.mesh.vertices);
  seq.paths.push_back(paths[0]);
  for (std::size_t i = 1; i < paths.size(); ++i) {
    seq.frames.push_back(read_frame(paths[i], i, seq.mesh, paths[0]));
    seq.paths.push_back(paths[i]);
  }
  return seq;
}

}  // namespace mccd
