#include <mccd/geometry/mesh_io.h>

#include <gtest/gtest.h>

#include <mccd/geometry/topology.h>
#include "fixtures/shapes.h"
#include <unistd.h>

#include <atomic>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <mccd/geometry/error.h>
#include "support/errors.h"
#include "support/data.h"

using namespace mccd;
namespace fs = std::filesystem;

namespace {

/// A fresh folder under the system temp folder, removed with its contents at the end.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    std::random_device rd;
    path_ = fs::temp_directory_path() /
            ("mccd_io_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" + std::to_string(rd()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const fs::path& path() const { return path_; }
  /// Writes bytes exactly as given and returns the path.
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string p = file(name);
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }

 private:
  fs::path path_;
};

using mccd::test::error_of;

#define EXPECT_ERROR_CONTAINS(stmt, text)                                              \
  do {                                                                                 \
    const std::string msg_ = error_of([&] { (void)(stmt); });                          \
    EXPECT_NE(msg_.find(text), std::string::npos) << "message: " << msg_ << "\nwanted: " << (text); \
  } while (0)

/// Binary payload builder for one byte order.
struct Bytes {
  bool big = false;
  std::string s;
  template <class T>
  Bytes& put(T v) {
    char tmp[sizeof(T)];
    std::memcpy(tmp, &v, sizeof(T));
    const bool host_big = std::endian::native == std::endian::big;
    if (big != host_big) std::reverse(tmp, tmp + sizeof(T));
    s.append(tmp, sizeof(T));
    return *this;
  }
  /// Writes `v` as the PLY scalar type named `type`.
  Bytes& put_as(const std::string& type, double v) {
    if (type == "char" || type == "int8") return put<std::int8_t>(static_cast<std::int8_t>(v));
    if (type == "uchar" || type == "uint8") return put<std::uint8_t>(static_cast<std::uint8_t>(v));
    if (type == "short" || type == "int16") return put<std::int16_t>(static_cast<std::int16_t>(v));
    if (type == "ushort" || type == "uint16") return put<std::uint16_t>(static_cast<std::uint16_t>(v));
    if (type == "int" || type == "int32") return put<std::int32_t>(static_cast<std::int32_t>(v));
    if (type == "uint" || type == "uint32") return put<std::uint32_t>(static_cast<std::uint32_t>(v));
    if (type == "float" || type == "float32") return put<float>(static_cast<float>(v));
    if (type == "double" || type == "float64") return put<double>(v);
    ADD_FAILURE() << "unknown type " << type;
    return *this;
  }
};

const std::vector<std::string> kAllTypes{"char",  "uchar",  "short",  "ushort", "int",   "uint",   "int8",    "uint8",
                                         "int16", "uint16", "int32",  "uint32", "float", "double", "float32", "float64"};
const std::vector<std::string> kIntTypes{"char",  "uchar",  "short", "ushort", "int",   "uint",
                                         "int8",  "uint8",  "int16", "uint16", "int32", "uint32"};

/// A small test mesh described as polygons: a quad, a triangle and a pentagon over 8 vertices.
/// Coordinates are small non-negative integers so every PLY scalar type holds them exactly.
struct PolyMesh {
  std::vector<std::array<double, 3>> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                       {2, 0, 1}, {3, 1, 2}, {4, 2, 3}, {5, 3, 4}};
  std::vector<std::vector<int>> f{{0, 1, 2, 3}, {1, 4, 2}, {4, 5, 6, 7, 2}};
  /// Fan triangulation the readers must produce.
  std::vector<Triangle> triangles() const {
    return {{0, 1, 2}, {0, 2, 3}, {1, 4, 2}, {4, 5, 6}, {4, 6, 7}, {4, 7, 2}};
  }
};

enum class Fmt { Ascii, LE, BE };
const char* fmt_name(Fmt f) {
  return f == Fmt::Ascii ? "ascii" : f == Fmt::LE ? "binary_little_endian" : "binary_big_endian";
}

struct PlyOptions {
  Fmt fmt = Fmt::Ascii;
  std::string coord = "float";
  std::string count = "uchar";
  std::string index = "int";
  bool extras = false;  // extra vertex/face properties and extra elements before and after
};

std::string number_text(const std::string& type, double v) {
  if (type == "float" || type == "float32" || type == "double" || type == "float64") {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
  }
  return std::to_string(static_cast<long long>(v));
}

/// Writes PolyMesh as a PLY with the given types and format.
std::string make_ply(const PolyMesh& m, const PlyOptions& o) {
  std::string h = "ply\nformat " + std::string(fmt_name(o.fmt)) + " 1.0\ncomment generated by test_mesh_io\n";
  if (o.extras) h += "element material 2\nproperty list uchar float coeffs\nproperty int id\n";
  h += "element vertex " + std::to_string(m.v.size()) + "\n";
  if (o.extras) h += "property float nx\n";
  h += "property " + o.coord + " x\nproperty " + o.coord + " y\n";
  if (o.extras) h += "property uchar red\nproperty list ushort int neighbours\n";
  h += "property " + o.coord + " z\n";
  if (o.extras) h += "property double quality\n";
  h += "element face " + std::to_string(m.f.size()) + "\n";
  if (o.extras) h += "property short flags\n";
  h += "property list " + o.count + " " + o.index + " vertex_indices\n";
  if (o.extras) h += "property list uchar float texcoord\nproperty uchar red\n";
  if (o.extras) h += "element edge 1\nproperty int vertex1\nproperty int vertex2\nproperty list int uchar tags\n";
  h += "end_header\n";

  if (o.fmt == Fmt::Ascii) {
    std::string d;
    if (o.extras) d += "3 0.5 1.5 2.5 7\n0 -3\n";
    for (std::size_t i = 0; i < m.v.size(); ++i) {
      if (o.extras) d += "0.25 ";
      d += number_text(o.coord, m.v[i][0]) + " " + number_text(o.coord, m.v[i][1]) + " ";
      if (o.extras) d += "200 2 " + std::to_string(i) + " 9 ";
      d += number_text(o.coord, m.v[i][2]);
      if (o.extras) d += " 1e-3";
      d += "\n";
    }
    for (const auto& f : m.f) {
      if (o.extras) d += "-4 ";
      d += std::to_string(f.size());
      for (int i : f) {
        d += ' ';
        d += std::to_string(i);
      }
      if (o.extras) d += " 2 0.5 0.75 255";
      d += "\n";
    }
    if (o.extras) d += "0 1 3 9 8 7\n";
    return h + d;
  }
  Bytes b;
  b.big = o.fmt == Fmt::BE;
  if (o.extras) {
    b.put<std::uint8_t>(3).put<float>(0.5f).put<float>(1.5f).put<float>(2.5f).put<std::int32_t>(7);
    b.put<std::uint8_t>(0).put<std::int32_t>(-3);
  }
  for (std::size_t i = 0; i < m.v.size(); ++i) {
    if (o.extras) b.put<float>(0.25f);
    b.put_as(o.coord, m.v[i][0]).put_as(o.coord, m.v[i][1]);
    if (o.extras) b.put<std::uint8_t>(200).put<std::uint16_t>(2).put<std::int32_t>(int(i)).put<std::int32_t>(9);
    b.put_as(o.coord, m.v[i][2]);
    if (o.extras) b.put<double>(1e-3);
  }
  for (const auto& f : m.f) {
    if (o.extras) b.put<std::int16_t>(-4);
    b.put_as(o.count, double(f.size()));
    for (int i : f) b.put_as(o.index, i);
    if (o.extras) b.put<std::uint8_t>(2).put<float>(0.5f).put<float>(0.75f).put<std::uint8_t>(255);
  }
  if (o.extras) b.put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(3).put<std::uint8_t>(9).put<std::uint8_t>(8).put<std::uint8_t>(7);
  return h + b.s;
}

void expect_poly_mesh(const TriMesh& mesh, const PolyMesh& m, const std::string& path) {
  EXPECT_EQ(mesh.name, path);
  ASSERT_EQ(mesh.num_vertices(), m.v.size());
  for (std::size_t i = 0; i < m.v.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(mesh.vertices(i, k), m.v[i][k]) << "vertex " << i << " " << k;
  EXPECT_EQ(mesh.faces, m.triangles());
}

/// A mesh whose coordinates need all 17 digits.
TriMesh awkward_mesh() {
  TriMesh m = make_sphere_mesh(5, 7, 1.0 / 3.0, Vec3(0.1, -1e-17, 12345.678901234567));
  m.vertices(0, 0) = 1e-300;
  m.vertices(1, 1) = -0.0;
  m.vertices(2, 2) = 1.7976931348623157e308;
  m.vertices(3, 0) = 4.9406564584124654e-324;  // smallest subnormal
  m.vertices(4, 0) = 0.1;
  return m;
}

std::string header_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return all.substr(0, all.find("end_header"));
}

/// Names of the entries of a folder.
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> out;
  for (auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

const std::string kAsciiHeader =
    "ply\n"                                     // 1
    "format ascii 1.0\n"                        // 2
    "element vertex 4\n"                        // 3
    "property float x\n"                        // 4
    "property float y\n"                        // 5
    "property float z\n"                        // 6
    "element face 2\n"                          // 7
    "property list uchar int vertex_indices\n"  // 8
    "end_header\n";                             // 9, data starts on line 10

const std::string kAsciiVertices = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n";  // lines 10-13

}  // namespace

// ------------------------------------------------------------------------------------------
// PLY reading: formats and types
// ------------------------------------------------------------------------------------------

TEST(PlyReader, AsciiBasic) {
  TempDir dir;
  const std::string p = dir.write("a.ply", kAsciiHeader + kAsciiVertices + "3 0 1 2\n3 2 1 3\n");
  const TriMesh m = read_ply(p);
  EXPECT_EQ(m.name, p);
  ASSERT_EQ(m.num_vertices(), 4u);
  EXPECT_EQ(m.vertices.point(3), Vec3(1, 1, 0));
  EXPECT_EQ(m.faces, (std::vector<Triangle>{{0, 1, 2}, {2, 1, 3}}));
}

TEST(PlyReader, AsciiCrlfCommentsBlankLinesAndFractions) {
  TempDir dir;
  const std::string text =
      "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info nothing\r\nelement vertex 3\r\n"
      "property double x\r\nproperty double y\r\nproperty double z\r\nelement face 1\r\n"
      "property list uchar uint vertex_index\r\nend_header\r\n"
      "  0.1 -2.5e-3 +7\r\n\r\n1e2\t0.3333333333333333 -0\r\n0 1 0\r\n3 0 1 2\r\n\r\n";
  const TriMesh m = read_ply(dir.write("crlf.ply", text));
  ASSERT_EQ(m.num_vertices(), 3u);
  EXPECT_EQ(m.vertices(0, 0), 0.1);
  EXPECT_EQ(m.vertices(0, 1), -2.5e-3);
  EXPECT_EQ(m.vertices(0, 2), 7.0);
  EXPECT_EQ(m.vertices(1, 0), 100.0);
  EXPECT_EQ(m.vertices(1, 1), 0.3333333333333333);
  EXPECT_EQ(m.faces, (std::vector<Triangle>{{0, 1, 2}}));
}

TEST(PlyReader, EveryCoordinateTypeInEveryFormat) {
  TempDir dir;
  const PolyMesh pm;
  for (Fmt fmt : {Fmt::Ascii, Fmt::LE, Fmt::BE})
    for (const std::string& type : kAllTypes) {
      SCOPED_TRACE(std::string(fmt_name(fmt)) + " " + type);
      PlyOptions o;
      o.fmt = fmt;
      o.coord = type;
      const std::string p = dir.write("c_" + type + "_" + fmt_name(fmt) + ".ply", make_ply(pm, o));
      expect_poly_mesh(read_ply(p), pm, p);
    }
}

TEST(PlyReader, EveryListTypeInEveryFormat) {
  TempDir dir;
  const PolyMesh pm;
  for (Fmt fmt : {Fmt::Ascii, Fmt::LE, Fmt::BE})
    for (const std::string& count : kIntTypes)
      for (const std::string& index : kIntTypes) {
        SCOPED_TRACE(std::string(fmt_name(fmt)) + " list " + count + " " + index);
        PlyOptions o;
        o.fmt = fmt;
        o.count = count;
        o.index = index;
        o.coord = "double";
        const std::string p = dir.write("l_" + count + "_" + index + "_" + fmt_name(fmt) + ".ply", make_ply(pm, o));
        expect_poly_mesh(read_ply(p), pm, p);
      }
}

TEST(PlyReader, ExtraPropertiesAndElementsSkippedInEveryFormat) {
  TempDir dir;
  const PolyMesh pm;
  for (Fmt fmt : {Fmt::Ascii, Fmt::LE, Fmt::BE})
    for (const char* coord : {"float", "double"})
      for (const char* index : {"int", "uint"}) {
        SCOPED_TRACE(std::string(fmt_name(fmt)) + " " + coord + " " + index);
        PlyOptions o;
        o.fmt = fmt;
        o.coord = coord;
        o.index = index;
        o.extras = true;
        const std::string p = dir.write(std::string("x_") + fmt_name(fmt) + coord + index + ".ply", make_ply(pm, o));
        expect_poly_mesh(read_ply(p), pm, p);
      }
}

TEST(PlyReader, BinaryFloatAndDoubleValuesExact) {
  TempDir dir;
  for (bool big : {false, true}) {
    // float: 0.1f widened exactly; double: full precision
    Bytes b;
    b.big = big;
    b.put<float>(0.1f).put<float>(-1e-30f).put<float>(3.25f);
    b.put<float>(1).put<float>(0).put<float>(0);
    b.put<float>(0).put<float>(1).put<float>(0);
    b.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
    const std::string fmt = big ? "binary_big_endian" : "binary_little_endian";
    const std::string hf = "ply\nformat " + fmt +
                           " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const TriMesh mf = read_ply(dir.write("f" + fmt + ".ply", hf + b.s));
    EXPECT_EQ(mf.vertices(0, 0), double(0.1f));
    EXPECT_EQ(mf.vertices(0, 1), double(-1e-30f));
    EXPECT_EQ(mf.vertices(0, 2), 3.25);

    Bytes d;
    d.big = big;
    d.put<double>(0.1).put<double>(1.0 / 3.0).put<double>(-1e-300);
    d.put<double>(1).put<double>(0).put<double>(0);
    d.put<double>(0).put<double>(1).put<double>(0);
    d.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
    const std::string hd = "ply\nformat " + fmt +
                           " 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const TriMesh md = read_ply(dir.write("d" + fmt + ".ply", hd + d.s));
    EXPECT_EQ(md.vertices(0, 0), 0.1);
    EXPECT_EQ(md.vertices(0, 1), 1.0 / 3.0);
    EXPECT_EQ(md.vertices(0, 2), -1e-300);
    EXPECT_EQ(md.faces, (std::vector<Triangle>{{0, 1, 2}}));
  }
}

TEST(PlyReader, MixedCoordinateTypes) {
  TempDir dir;
  Bytes b;
  b.put<double>(0.5).put<std::int16_t>(-2).put<float>(1.5f);
  b.put<double>(1).put<std::int16_t>(0).put<float>(0);
  b.put<double>(0).put<std::int16_t>(1).put<float>(0);
  b.put<std::uint8_t>(3).put<std::uint16_t>(0).put<std::uint16_t>(1).put<std::uint16_t>(2);
  const std::string h =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty short y\n"
      "property float z\nelement face 1\nproperty list uint8 uint16 vertex_indices\nend_header\n";
  const TriMesh m = read_ply(dir.write("mixed.ply", h + b.s));
  EXPECT_EQ(m.vertices.point(0), Vec3(0.5, -2, 1.5));
}

TEST(PlyReader, PointCloudWithoutFacesAndEmptyElements) {
  TempDir dir;
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 0\nproperty list uchar int vertex_indices\nend_header\n1 2 3\n4 5 6\n";
  const TriMesh m = read_ply(dir.write("cloud.ply", text));
  EXPECT_EQ(m.num_vertices(), 2u);
  EXPECT_EQ(m.num_faces(), 0u);
  const std::string nofaces =
      "ply\nformat binary_big_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n";
  EXPECT_EQ(read_ply(dir.write("none.ply", nofaces)).num_vertices(), 0u);
}

TEST(PlyReader, FacesBeforeVertices) {
  TempDir dir;
  Bytes b;
  b.big = true;
  b.put<std::uint8_t>(3).put<std::uint32_t>(2).put<std::uint32_t>(1).put<std::uint32_t>(0);
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) b.put<float>(v);
  const std::string h =
      "ply\nformat binary_big_endian 1.0\nelement face 1\nproperty list uchar uint vertex_indices\n"
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  const TriMesh m = read_ply(dir.write("fv.ply", h + b.s));
  EXPECT_EQ(m.faces, (std::vector<Triangle>{{2, 1, 0}}));
  EXPECT_EQ(m.vertices.point(1), Vec3(1, 0, 0));
}

// ------------------------------------------------------------------------------------------
// PLY reading: errors
// ------------------------------------------------------------------------------------------

TEST(PlyReaderErrors, MissingAndEmptyFiles) {
  TempDir dir;
  const std::string missing = dir.file("nope.ply");
  EXPECT_ERROR_CONTAINS(read_ply(missing), missing + ": cannot open");
  EXPECT_ERROR_CONTAINS(read_mesh(missing), missing + ": cannot open");
  EXPECT_ERROR_CONTAINS(read_ply(dir.path().string()), ": cannot open");
  const std::string empty = dir.write("empty.ply", "");
  EXPECT_EQ(error_of([&] { read_ply(empty); }), empty + ": empty file");
  const std::string blank = dir.write("blank.ply", " \n\n");
  EXPECT_EQ(error_of([&] { read_ply(blank); }), blank + ": empty file");
}

TEST(PlyReaderErrors, Header) {
  TempDir dir;
  auto err = [&](const std::string& text) { return error_of([&] { read_ply(dir.write("h.ply", text)); }); };
  const std::string p = dir.file("h.ply");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"), p + ": header: missing 'end_header'");
  EXPECT_EQ(err("plx\nformat ascii 1.0\nend_header\n"), p + ": header: not a PLY file (the first line must be 'ply')");
  EXPECT_EQ(err("ply\nformat binary_middle_endian 1.0\nend_header\n"),
            p + ": line 2: header: unknown format 'binary_middle_endian' (expected ascii, binary_little_endian or "
                "binary_big_endian)");
  EXPECT_EQ(err("ply\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n"),
            p + ": header: missing 'format' line");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n"),
            p + ": line 4: header: unknown property type 'quad'");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nproperty float x\nend_header\n"),
            p + ": line 3: header: property before any element");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex many\nend_header\n"),
            p + ": line 3: header: expected a non-negative element count for 'vertex', got 'many'");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex -2\nend_header\n"),
            p + ": line 3: header: expected a non-negative element count for 'vertex', got '-2'");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"),
            p + ": header: no 'vertex' element");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nend_header\n"),
            p + ": header: element 'vertex' has no property 'z'");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 0\nproperty list uchar int corners\nend_header\n"),
            p + ": header: element 'face' has no list property 'vertex_indices'");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 0\nproperty list float int vertex_indices\nend_header\n"),
            p + ": line 8: header: the count type of a list must be an integer type, got 'float'");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 0\nproperty list uchar float vertex_indices\nend_header\n"),
            p + ": header: face property 'vertex_indices' must hold integers");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 0\nproperty int vertex_indices\nend_header\n"),
            p + ": header: face property 'vertex_indices' must be a list");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nelement vertex 0\nelement vertex 0\nend_header\n"),
            p + ": line 4: header: duplicate element 'vertex'");
  EXPECT_EQ(err("ply\nformat ascii 1.0\nbogus line\nend_header\n"), p + ": line 3: header: unknown keyword 'bogus'");
}

TEST(PlyReaderErrors, AsciiBadNumber) {
  TempDir dir;
  const std::string text = "ply\nformat ascii 1.0\ncomment one\ncomment two\ncomment three\n"
                           "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n"  // 12 lines
                           "0 0 0\n1 0 0\n0 1 0\n"                                                 // 13-15
                           "1 abc 0\n"                                                             // 16: vertex 3
                           "1 1 1\n3 0 1 2\n";
  const std::string p = dir.write("x.ply", text);
  EXPECT_EQ(error_of([&] { read_ply(p); }), p + ": line 16: expected a number for property 'y' of vertex 3, got 'abc'");
}

TEST(PlyReaderErrors, AsciiStructure) {
  TempDir dir;
  const std::string p = dir.file("s.ply");
  auto err = [&](const std::string& body) { return error_of([&] { read_ply(dir.write("s.ply", kAsciiHeader + body)); }); };
  // too few vertices / faces: the file ends early
  EXPECT_EQ(err("0 0 0\n1 0 0\n"), p + ": line 12: expected vertex 2 of 4, reached the end of the file");
  EXPECT_EQ(err(kAsciiVertices + "3 0 1 2\n"), p + ": line 15: expected face 1 of 2, reached the end of the file");
  // more data than declared
  EXPECT_EQ(err(kAsciiVertices + "3 0 1 2\n3 2 1 3\n3 1 2 3\n"),
            p + ": line 16: unexpected data after the last element ('3 1 2 3'): the element counts in the header are "
                "wrong");
  // a value missing and one too many on a line
  EXPECT_EQ(err("0 0 0\n1 0\n"), p + ": line 11: expected a number for property 'z' of vertex 1, got the end of the line");
  EXPECT_EQ(err("0 0 0 7\n"), p + ": line 10: vertex 0: unexpected extra value '7' (the header declares 3 properties)");
  EXPECT_EQ(err(kAsciiVertices + "3 0 1 2 3\n3 2 1 3\n"),
            p + ": line 14: face 0: unexpected extra value '3' (the header declares 1 properties)");
  // list problems
  EXPECT_EQ(err(kAsciiVertices + "3 0 1\n"),
            p + ": line 14: list 'vertex_indices' of face 0: expected 3 items, got 2");
  EXPECT_EQ(err(kAsciiVertices + "x 0 1 2\n"),
            p + ": line 14: expected an item count for list 'vertex_indices' of face 0, got 'x'");
  EXPECT_EQ(err(kAsciiVertices + "3 0 1.5 2\n"),
            p + ": line 14: expected an integer in list 'vertex_indices' of face 0, got '1.5'");
  EXPECT_EQ(err(kAsciiVertices + "3 0 1 2\n2 0 1\n"), p + ": line 15: face 1: expected at least 3 vertex indices, got 2");
  EXPECT_EQ(err(kAsciiVertices + "3 0 1 2\n0\n"), p + ": line 15: face 1: expected at least 3 vertex indices, got 0");
  EXPECT_EQ(err(kAsciiVertices + "3 0 1 2\n3 2 1 4\n"), p + ": line 15: face 1: vertex index 4 out of range [0, 4)");
  EXPECT_EQ(err(kAsciiVertices + "3 0 1 2\n3 2 -1 3\n"), p + ": line 15: face 1: vertex index -1 out of range [0, 4)");
  EXPECT_EQ(err(kAsciiVertices + "3 0 1 2\n3 2 1 2\n"), p + ": line 15: face 1: repeated vertex index (2, 1, 2)");
  // non-finite coordinates
  EXPECT_EQ(err("0 0 0\n1 nan 0\n"), p + ": line 11: coordinate y of vertex 1 is not finite ('nan')");
  EXPECT_EQ(err("0 0 0\n1 0 0\n0 1 -inf\n"), p + ": line 12: coordinate z of vertex 2 is not finite ('-inf')");
}

TEST(PlyReaderErrors, AsciiSkippedListInOtherElement) {
  TempDir dir;
  const std::string text =
      "ply\nformat ascii 1.0\nelement extra 1\nproperty list uchar float values\n"
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"  // 9 lines
      "3 1 2\n";                                                                             // one item short
  const std::string p = dir.write("e.ply", text);
  EXPECT_EQ(error_of([&] { read_ply(p); }), p + ": line 10: list 'values' of extra 0: expected 3 items, got 2");
  const std::string bad = dir.write("e2.ply", text.substr(0, text.size() - 6) + "2 1 q\n0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_EQ(error_of([&] { read_ply(bad); }), bad + ": line 10: expected a number in list 'values' of extra 0, got 'q'");
}

TEST(PlyReaderErrors, BinaryTruncated) {
  TempDir dir;
  for (bool big : {false, true}) {
    const std::string fmt = big ? "binary_big_endian" : "binary_little_endian";
    const std::string h = "ply\nformat " + fmt +
                          " 1.0\nelement vertex 100\nproperty float x\nproperty float y\nproperty float z\n"
                          "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
    Bytes b;
    b.big = big;
    for (int i = 0; i < 17 * 3 + 2; ++i) b.put<float>(float(i));  // 17 vertices and a part
    const std::string p = dir.write("t.ply", h + b.s);
    EXPECT_EQ(error_of([&] { read_ply(p); }), p + ": truncated binary data: vertex 17 of 100");

    // all vertices, then the second face cut short in its list, then in its count
    const std::string h3 = "ply\nformat " + fmt +
                           " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
    Bytes v;
    v.big = big;
    for (int i = 0; i < 9; ++i) v.put<float>(float(i % 4));
    v.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
    Bytes cut = v;
    cut.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1);
    const std::string p2 = dir.write("t2.ply", h3 + cut.s);
    EXPECT_EQ(error_of([&] { read_ply(p2); }), p2 + ": truncated binary data: face 1 of 2");
    const std::string p3 = dir.write("t3.ply", h3 + v.s);
    EXPECT_EQ(error_of([&] { read_ply(p3); }), p3 + ": truncated binary data: face 1 of 2");
    // a skipped scalar property of a list element cut short
    const std::string h4 = "ply\nformat " + fmt +
                           " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nproperty double q\nend_header\n";
    Bytes w = v;
    w.put<std::uint8_t>(1);
    const std::string p4 = dir.write("t4.ply", h4 + w.s);
    EXPECT_EQ(error_of([&] { read_ply(p4); }), p4 + ": truncated binary data: face 0 of 1");
    // header only
    const std::string p5 = dir.write("t5.ply", h3);
    EXPECT_EQ(error_of([&] { read_ply(p5); }), p5 + ": truncated binary data: vertex 0 of 3");
  }
}

TEST(PlyReaderErrors, BinaryCountsAndIndices) {
  TempDir dir;
  for (bool big : {false, true}) {
    const std::string fmt = big ? "binary_big_endian" : "binary_little_endian";
    const std::string h = "ply\nformat " + fmt +
                          " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                          "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
    auto file = [&](std::vector<std::vector<int>> faces, float y1 = 0, std::string tail = "") {
      Bytes b;
      b.big = big;
      for (float v : {0.f, 0.f, 0.f, 1.f, y1, 0.f, 0.f, 1.f, 0.f, 1.f, 1.f, 0.f}) b.put<float>(v);
      for (auto& f : faces) {
        b.put<std::uint8_t>(std::uint8_t(f.size()));
        for (int i : f) b.put<std::int32_t>(i);
      }
      return dir.write("b.ply", h + b.s + tail);
    };
    const std::string p = dir.file("b.ply");
    EXPECT_NO_THROW(read_ply(file({{0, 1, 2}, {2, 1, 3}})));
    EXPECT_NO_THROW(read_ply(file({{0, 1, 2}, {2, 1, 3}}, 0, "\n")));  // a trailing newline is tolerated
    EXPECT_EQ(error_of([&] { read_ply(file({{0, 1, 2}, {2, 1, 7}})); }), p + ": face 1: vertex index 7 out of range [0, 4)");
    EXPECT_EQ(error_of([&] { read_ply(file({{0, 1, 2}, {2, -5, 3}})); }), p + ": face 1: vertex index -5 out of range [0, 4)");
    EXPECT_EQ(error_of([&] { read_ply(file({{0, 1}, {2, 1, 3}})); }), p + ": face 0: expected at least 3 vertex indices, got 2");
    EXPECT_EQ(error_of([&] { read_ply(file({{0, 1, 2}, {3, 1, 3}})); }), p + ": face 1: repeated vertex index (3, 1, 3)");
    EXPECT_EQ(error_of([&] { read_ply(file({{0, 1, 2}, {2, 1, 3}, {0, 1, 3}})); }),
              p + ": 13 bytes of unexpected data after the last element: the element counts in the header are wrong");
    EXPECT_ERROR_CONTAINS(read_ply(file({{0, 1, 2}, {2, 1, 3}}, std::numeric_limits<float>::quiet_NaN())),
                          p + ": vertex 1: coordinate y is not finite");
    EXPECT_ERROR_CONTAINS(read_ply(file({{0, 1, 2}, {2, 1, 3}}, std::numeric_limits<float>::infinity())),
                          p + ": vertex 1: coordinate y is not finite");
  }
}

TEST(PlyReaderErrors, BinaryNegativeListCount) {
  TempDir dir;
  Bytes b;
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) b.put<float>(v);
  b.put<std::int8_t>(-3);
  const std::string h =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list char int vertex_indices\nend_header\n";
  const std::string p = dir.write("n.ply", h + b.s);
  EXPECT_EQ(error_of([&] { read_ply(p); }), p + ": face 0: negative item count -3 for list 'vertex_indices'");
}

// ------------------------------------------------------------------------------------------
// OBJ reading
// ------------------------------------------------------------------------------------------

TEST(ObjReader, AllFaceFormsNegativeIndicesAndPolygons) {
  TempDir dir;
  const std::string text =
      "# a comment\r\n"
      "mtllib none.mtl\r\n"
      "o thing\r\n"
      "\r\n"
      "v 0 0 0\r\n"
      "v 1 0 0 1.0\r\n"  // optional w
      "  v\t1 1 0\r\n"
      "v 0 1 0 0.5 0.5 0.5\r\n"  // vertex colour
      "vt 0 0\r\nvt 1 0\r\nvn 0 0 1\r\n"
      "g group\r\ns off\r\nusemtl red\r\n"
      "f 1 2 3\r\n"
      "f 1/1 3/2 4/1\r\n"
      "f 1//1 2//1 4//1\r\n"
      "f 2/1/1 3/2/1 4/1/1\r\n"
      "v 2 0 0\r\n"
      "v 2 1 0\r\n"
      "f -4 -2 -1 -3\r\n"  // quad (3, 5, 6, 4) with relative indices (1-based)
      "l 1 2\r\n"
      "f 1 2 5 6 3 # a pentagon, with a comment after it";  // and no final newline
  const std::string p = dir.write("all.obj", text);
  const TriMesh m = read_obj(p);
  EXPECT_EQ(m.name, p);
  ASSERT_EQ(m.num_vertices(), 6u);
  EXPECT_EQ(m.vertices.point(2), Vec3(1, 1, 0));
  EXPECT_EQ(m.vertices.point(5), Vec3(2, 1, 0));
  const std::vector<Triangle> expected{{0, 1, 2}, {0, 2, 3}, {0, 1, 3}, {1, 2, 3},
                                       {2, 4, 5}, {2, 5, 3},                        // quad, relative
                                       {0, 1, 4}, {0, 4, 5}, {0, 5, 2}};            // pentagon
  EXPECT_EQ(m.faces, expected);
  EXPECT_EQ(read_mesh(p).faces, expected);
}

TEST(ObjReader, ReadMeshChoosesByExtension) {
  TempDir dir;
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(read_mesh(dir.write("UPPER.OBJ", obj)).num_faces(), 1u);
  EXPECT_EQ(read_mesh(dir.write("mixed.Ply", kAsciiHeader + kAsciiVertices + "3 0 1 2\n3 2 1 3\n")).num_faces(), 2u);
  const std::string stl = dir.write("m.stl", obj);
  EXPECT_EQ(error_of([&] { read_mesh(stl); }), stl + ": unknown mesh file type '.stl' (expected .obj or .ply)");
  const std::string none = dir.write("noext", obj);
  EXPECT_EQ(error_of([&] { read_mesh(none); }), none + ": unknown mesh file type '(none)' (expected .obj or .ply)");
}

TEST(ObjReader, VerticesOnly) {
  TempDir dir;
  const TriMesh m = read_obj(dir.write("pts.obj", "v 1 2 3\nv 4 5 6"));  // no final newline
  EXPECT_EQ(m.num_vertices(), 2u);
  EXPECT_EQ(m.vertices.point(1), Vec3(4, 5, 6));
  EXPECT_EQ(m.num_faces(), 0u);
}

TEST(ObjReaderErrors, Everything) {
  TempDir dir;
  const std::string p = dir.file("e.obj");
  auto err = [&](const std::string& text) { return error_of([&] { read_obj(dir.write("e.obj", text)); }); };
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";  // lines 1-3
  EXPECT_EQ(err(""), p + ": empty file");
  EXPECT_EQ(err("\n  \r\n"), p + ": empty file");
  EXPECT_EQ(err("# only a comment\nvt 0 0\n"), p + ": no vertices or faces (no 'v' or 'f' lines)");
  EXPECT_EQ(err(v3 + "v 1 abc 0\n"), p + ": line 4: expected a number for coordinate y of vertex 4, got 'abc'");
  EXPECT_EQ(err(v3 + "v 1 2\n"), p + ": line 4: expected 3 coordinates for vertex 4, got 2");
  EXPECT_EQ(err("v 0 0 nan\n"), p + ": line 1: coordinate z of vertex 1 is not finite ('nan')");
  EXPECT_EQ(err("v inf 0 0\n"), p + ": line 1: coordinate x of vertex 1 is not finite ('inf')");
  EXPECT_EQ(err(v3 + "f 1 2\n"), p + ": line 4: face with fewer than 3 vertices (2)");
  EXPECT_EQ(err(v3 + "f\n"), p + ": line 4: face with fewer than 3 vertices (0)");
  EXPECT_EQ(err(v3 + "f 0 1 2\n"), p + ": line 4: vertex index 0 is invalid (OBJ indices start at 1)");
  EXPECT_EQ(err(v3 + "f -1 -2 -4\n"),
            p + ": line 4: relative vertex index -4 points before the first vertex (3 vertices so far)");
  EXPECT_EQ(err(v3 + "f 1 2 x\n"), p + ": line 4: expected a vertex index (a, a/b, a//c or a/b/c) in face, got 'x'");
  EXPECT_EQ(err(v3 + "f 1 2 3x/1\n"), p + ": line 4: expected a vertex index (a, a/b, a//c or a/b/c) in face, got '3x/1'");
  EXPECT_EQ(err(v3 + "f 1 2 1\n"), p + ": line 4: face: repeated vertex index (0, 1, 0)");
  EXPECT_EQ(err(v3 + "f 1 2 4\n# later\n"), p + ": line 4: vertex index 4 out of range [1, 3]");
  EXPECT_EQ(err(v3 + "f 1 2 99999999999\n"), p + ": line 4: vertex index '99999999999' is too large");
  const std::string missing = dir.file("missing.obj");
  EXPECT_ERROR_CONTAINS(read_obj(missing), missing + ": cannot open");
}

TEST(ObjReader, ForwardReferenceIsAccepted) {
  TempDir dir;
  // OBJ allows a face to name a vertex defined further down
  const TriMesh m = read_obj(dir.write("fwd.obj", "v 0 0 0\nf 1 2 3\nv 1 0 0\nv 0 1 0\n"));
  EXPECT_EQ(m.faces, (std::vector<Triangle>{{0, 1, 2}}));
}

// ------------------------------------------------------------------------------------------
// Writers
// ------------------------------------------------------------------------------------------

TEST(PlyWriter, RoundTripIsExact) {
  TempDir dir;
  const TriMesh m = awkward_mesh();
  const std::string p = dir.file("out.ply");
  write_ply(p, m);
  const TriMesh r = read_ply(p);
  EXPECT_EQ(r.faces, m.faces);
  ASSERT_EQ(r.num_vertices(), m.num_vertices());
  for (std::size_t v = 0; v < m.vertices.rows(); ++v)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(std::bit_cast<std::uint64_t>(r.vertices(v, k)), std::bit_cast<std::uint64_t>(m.vertices(v, k)));
  const std::string h = header_of(p);
  EXPECT_NE(h.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(h.find("property double x"), std::string::npos);
  EXPECT_NE(h.find("property list uchar int vertex_indices"), std::string::npos);
  EXPECT_EQ(h.find("red"), std::string::npos);
  EXPECT_EQ(fs::file_size(p), h.size() + std::string("end_header\n").size() + m.num_vertices() * 24 + m.num_faces() * 13);
  EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"out.ply"});  // no temporary left behind
}

TEST(PlyWriter, FaceColours) {
  TempDir dir;
  const TriMesh m = make_grid_mesh(2);
  FaceColors colors;
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    colors.push_back({std::uint8_t(f * 10), std::uint8_t(255 - f), std::uint8_t(7)});
  const std::string p = dir.file("colours.ply");
  write_ply(p, m, colors);
  const std::string h = header_of(p);
  EXPECT_NE(h.find("property uchar red\nproperty uchar green\nproperty uchar blue\n"), std::string::npos);
  const std::size_t data = h.size() + std::string("end_header\n").size();
  EXPECT_EQ(fs::file_size(p), data + m.num_vertices() * 24 + m.num_faces() * 16);
  // the colour of face 3 sits after its three indices
  std::ifstream in(p, std::ios::binary);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = data + m.num_vertices() * 24 + 3 * 16 + 13;
  EXPECT_EQ(std::uint8_t(all[at]), 30);
  EXPECT_EQ(std::uint8_t(all[at + 1]), 252);
  EXPECT_EQ(std::uint8_t(all[at + 2]), 7);
  // and the reader skips them
  const TriMesh r = read_ply(p);
  EXPECT_EQ(r.faces, m.faces);
  EXPECT_EQ(r.vertices, m.vertices);
}

TEST(PlyWriter, OverwritesExistingFile) {
  TempDir dir;
  const std::string p = dir.write("over.ply", "old contents");
  write_ply(p, make_grid_mesh(1));
  EXPECT_EQ(read_ply(p).num_faces(), 2u);
  EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"over.ply"});
}

TEST(PlyWriter, FailuresLeaveNoFile) {
  TempDir dir;
  const TriMesh m = make_grid_mesh(2);
  // a folder that does not exist
  const std::string nodir = dir.file("no/such/folder/x.ply");
  EXPECT_ERROR_CONTAINS(write_ply(nodir, m), nodir + ": cannot write");
  EXPECT_FALSE(fs::exists(nodir));
  // the target is a folder: the temporary is written, the rename fails, the temporary goes
  fs::create_directory(dir.file("target.ply"));
  EXPECT_ERROR_CONTAINS(write_ply(dir.file("target.ply"), m), dir.file("target.ply") + ": cannot write");
  EXPECT_ERROR_CONTAINS(write_obj(dir.file("target.ply"), m), dir.file("target.ply") + ": cannot write");
  EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"target.ply"});
  // wrong number of colours, out-of-range index: refused before anything is written
  const std::string p = dir.file("c.ply");
  EXPECT_ERROR_CONTAINS(write_ply(p, m, FaceColors(3)), p + ": cannot write: 3 face colours for 8 faces");
  TriMesh bad = m;
  bad.faces[5][1] = 100;
  EXPECT_ERROR_CONTAINS(write_ply(p, bad), p + ": cannot write: face 5: vertex index 100 out of range [0, 9)");
  EXPECT_ERROR_CONTAINS(write_obj(dir.file("c.obj"), bad), "face 5: vertex index 100 out of range");
  EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"target.ply"});
}

TEST(PlyWriter, UnwritableDirectory) {
  // A folder that cannot hold files even for root: its "parent" is a regular file.
  TempDir dir;
  const fs::path blocker = dir.path() / "not_a_folder";
  { std::ofstream(blocker) << "x"; }
  const std::string p = (blocker / "x.ply").string();
  EXPECT_ERROR_CONTAINS(write_ply(p, make_grid_mesh(1)), p + ": cannot write");
  EXPECT_FALSE(fs::exists(p));
  EXPECT_ERROR_CONTAINS(write_obj((blocker / "x.obj").string(), make_grid_mesh(1)), "cannot write");
  // nothing else appeared beside the blocker (no temporary left behind)
  std::size_t entries = 0;
  for ([[maybe_unused]] auto& e : fs::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1u);
}

TEST(ObjWriter, RoundTripIsExact) {
  TempDir dir;
  const TriMesh m = awkward_mesh();
  const std::string p = dir.file("out.obj");
  write_obj(p, m);
  const TriMesh r = read_obj(p);
  EXPECT_EQ(r.faces, m.faces);
  ASSERT_EQ(r.num_vertices(), m.num_vertices());
  for (std::size_t v = 0; v < m.vertices.rows(); ++v)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(std::bit_cast<std::uint64_t>(r.vertices(v, k)), std::bit_cast<std::uint64_t>(m.vertices(v, k)));
  // %.17g text
  std::ifstream in(p);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(all.find("\nv 1e-300 "), std::string::npos);
  EXPECT_NE(all.find("\nv 0.10000000000000001 "), std::string::npos);
  EXPECT_NE(all.find("\nf 1 2 3\n"), std::string::npos);
  EXPECT_EQ(listing(dir.path()), std::vector<std::string>{"out.obj"});
}

TEST(ObjWriter, FailureLeavesNoFile) {
  TempDir dir;
  const std::string p = dir.file("missing/x.obj");
  EXPECT_ERROR_CONTAINS(write_obj(p, make_grid_mesh(1)), p + ": cannot write");
  EXPECT_FALSE(fs::exists(p));
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

// ------------------------------------------------------------------------------------------
// Frames
// ------------------------------------------------------------------------------------------

TEST(FramePattern, Expansion) {
  TempDir dir;
  EXPECT_EQ(expand_frame_pattern("plain.ply"), std::vector<std::string>{"plain.ply"});  // as is, even if absent
  for (int i = 0; i < 4; ++i) dir.write("f" + std::string(i < 10 ? "00" : "0") + std::to_string(i) + ".ply", "x");
  EXPECT_EQ(expand_frame_pattern(dir.file("f%03d.ply")),
            (std::vector<std::string>{dir.file("f000.ply"), dir.file("f001.ply"), dir.file("f002.ply"), dir.file("f003.ply")}));
  // starting at 1, stopping at the first gap
  for (int i : {1, 2, 3, 5}) dir.write("g" + std::to_string(i) + ".obj", "x");
  EXPECT_EQ(expand_frame_pattern(dir.file("g%d.obj")),
            (std::vector<std::string>{dir.file("g1.obj"), dir.file("g2.obj"), dir.file("g3.obj")}));
  // other conversions and a literal percent
  dir.write("100%_7.ply", "x");
  dir.write("100%_0.ply", "x");
  EXPECT_EQ(expand_frame_pattern(dir.file("100%%_%u.ply")), std::vector<std::string>{dir.file("100%_0.ply")});
  dir.write("h 0.ply", "x");
  EXPECT_EQ(expand_frame_pattern(dir.file("h%2i.ply")), std::vector<std::string>{dir.file("h 0.ply")});
}

TEST(FramePattern, Errors) {
  TempDir dir;
  const std::string none = dir.file("none%04d.ply");
  EXPECT_EQ(error_of([&] { expand_frame_pattern(none); }),
            "frame pattern '" + none + "': no file found (tried '" + dir.file("none0000.ply") + "' and '" +
                dir.file("none0001.ply") + "')");
  for (const std::string bad : {"a%s.ply", "a%d_%d.ply", "a%.ply", "a%", "a%-3d.ply"})
    EXPECT_ERROR_CONTAINS(expand_frame_pattern(bad), "expected exactly one %d-style field");
}

namespace {
TriMesh shifted(const TriMesh& m, double dz) {
  TriMesh out = m;
  out.vertices.mat().col(2).array() += dz;
  return out;
}
}  // namespace

TEST(FrameSequence, ReadsListsAndPatterns) {
  TempDir dir;
  const TriMesh m = make_grid_mesh(3);
  write_ply(dir.file("frame000.ply"), m);
  write_obj(dir.file("frame001.obj"), shifted(m, 0.5));  // formats may be mixed
  write_ply(dir.file("frame002.ply"), shifted(m, 1.0));
  const FrameSequence s = read_frames({dir.file("frame000.ply"), dir.file("frame001.obj"), dir.file("frame002.ply")});
  ASSERT_EQ(s.frames.size(), 3u);
  EXPECT_EQ(s.mesh.faces, m.faces);
  EXPECT_EQ(s.mesh.vertices, m.vertices);
  EXPECT_EQ(s.mesh.name, dir.file("frame000.ply"));
  EXPECT_EQ(s.frames[0], m.vertices);
  EXPECT_EQ(s.frames[2], shifted(m, 1.0).vertices);
  EXPECT_EQ(s.paths[1], dir.file("frame001.obj"));

  for (int i = 0; i < 3; ++i) write_ply(dir.file("p" + std::to_string(i) + ".ply"), shifted(m, i));
  const FrameSequence q = read_frames({dir.file("p%d.ply")});
  ASSERT_EQ(q.frames.size(), 3u);
  EXPECT_EQ(q.paths, (std::vector<std::string>{dir.file("p0.ply"), dir.file("p1.ply"), dir.file("p2.ply")}));
  EXPECT_EQ(q.frames[1](0, 2), 1.0);

  // one file is a sequence of one frame
  EXPECT_EQ(read_frames({dir.file("p1.ply")}).frames.size(), 1u);
}

TEST(FrameSequence, MismatchedTopology) {
  TempDir dir;
  const TriMesh m = make_grid_mesh(2);
  const std::string a = dir.file("a.ply"), b = dir.file("b.ply");
  write_ply(a, m);
  TriMesh other = m;
  std::swap(other.faces[3][0], other.faces[3][1]);  // same vertices, other winding
  write_ply(b, other);
  EXPECT_EQ(error_of([&] { read_frames({a, a, b}); }),
            b + " (frame 2): face 3 is (" + std::to_string(other.faces[3][0]) + ", " + std::to_string(other.faces[3][1]) +
                ", " + std::to_string(other.faces[3][2]) + "), expected (" + std::to_string(m.faces[3][0]) + ", " +
                std::to_string(m.faces[3][1]) + ", " + std::to_string(m.faces[3][2]) + ") as in " + a);
  TriMesh fewer = m;
  fewer.faces.pop_back();
  write_ply(b, fewer);
  EXPECT_EQ(error_of([&] { read_frames({a, b}); }),
            b + " (frame 1): has 7 triangles, expected 8 as in " + a + " (first differing face 7)");
  write_ply(b, make_grid_mesh(3));
  EXPECT_EQ(error_of([&] { read_frames({a, b}); }), b + " (frame 1): has 16 vertices, expected 9 as in " + a);
  // a frame that does not load names its own file
  const std::string c = dir.write("c.ply", "");
  EXPECT_EQ(error_of([&] { read_frames({a, c}); }), c + ": empty file");
  EXPECT_EQ(error_of([&] { read_frames({}); }), "read_frames: no frame files given");
  EXPECT_ERROR_CONTAINS(read_frames({dir.file("zz%d.ply")}), "no file found");
}

// ------------------------------------------------------------------------------------------
// The real data set
// ------------------------------------------------------------------------------------------

TEST(MeshIoData, ClothBall) {
  const fs::path path = mccd::test::data_dir() / "toi/cloth-ball/frames/cloth_ball92.ply";
  MCCD_REQUIRE_DATA(path);
  const TriMesh m = read_mesh(path.string());
  EXPECT_EQ(m.name, path.string());
  EXPECT_EQ(m.num_vertices(), 46598u);
  EXPECT_EQ(m.num_faces(), 92230u);
  const MeshTopology t(m.num_vertices(), m.faces);
  EXPECT_EQ(t.num_edges(), 138825u);
  // the first edges, in libigl's order (sorted by (max, min))
  const std::vector<Edge> first(t.edges().begin(), t.edges().begin() + 6);
  EXPECT_EQ(first, (std::vector<Edge>{{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}, {5, 6}}));
  EXPECT_EQ(t.find_edge(1, 0), 0);
  EXPECT_EQ(t.find_edge(5, 6), 5);
  EXPECT_EQ(t.num_nonmanifold_edges(), 0u);
}

TEST(MeshIoData, ClothBallFrames) {
  const fs::path dir = mccd::test::data_dir() / "toi/cloth-ball/frames";
  MCCD_REQUIRE_DATA(dir / "cloth_ball93.ply");
  const FrameSequence s = read_frames({(dir / "cloth_ball92.ply").string(), (dir / "cloth_ball93.ply").string()});
  EXPECT_EQ(s.frames.size(), 2u);
  EXPECT_EQ(s.mesh.num_vertices(), 46598u);
  EXPECT_NE(s.frames[0], s.frames[1]);
}

TEST(MeshIoData, ClothFunnel) {
  const fs::path dir = mccd::test::data_dir() / "toi/cloth-funnel/frames";
  MCCD_REQUIRE_DATA(dir / "227.ply");
  const TriMesh m = read_mesh((dir / "227.ply").string());
  EXPECT_EQ(m.num_vertices(), 9450u);
  EXPECT_EQ(m.num_faces(), 18484u);
  if (fs::exists(dir / "228.ply")) {
    const FrameSequence s = read_frames({(dir / "227.ply").string(), (dir / "228.ply").string()});
    EXPECT_EQ(s.frames.size(), 2u);
    EXPECT_EQ(s.mesh.num_faces(), 18484u);
  }
}

// ------------------------------------------------------------------------------------------
// Line ends ("\n", "\r\n", lone "\r") in every text reader, and the values of an OBJ `v` line
// ------------------------------------------------------------------------------------------

namespace {
/// `text` with every "\n" replaced by `end`.
std::string with_line_ends(std::string text, const std::string& end) {
  std::string out;
  for (char c : text) c == '\n' ? out += end : out += c;
  return out;
}
}  // namespace

TEST(TextLineEnds, ObjCrOnlyFileLoadsEveryLine) {
  TempDir dir;
  // the reported defect: CR-only lines loaded as 1 vertex and 0 triangles, without an error
  const TriMesh m = read_obj(dir.write("cr.obj", "v 0 0 0\rv 1 0 0\rv 0 1 0\rv 0 0 1\rf 1 2 3\rf 1 2 4\r"));
  EXPECT_EQ(m.num_vertices(), 4u);
  EXPECT_EQ(m.faces, (std::vector<Triangle>{{0, 1, 2}, {0, 1, 3}}));
  const std::string text = "# corner\nv 0 0 0\nv 1 0 0\nv 0 1 0 # c\n\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4";
  const TriMesh lf = read_obj(dir.write("lf.obj", text));
  for (const char* end : {"\r\n", "\r"}) {
    const TriMesh other = read_obj(dir.write("other.obj", with_line_ends(text, end)));
    EXPECT_EQ(other.vertices, lf.vertices);
    EXPECT_EQ(other.faces, lf.faces);
  }
  // mixed line ends in one file; lone-CR lines count as lines in messages
  const TriMesh mixed = read_obj(dir.write("mixed.obj", "v 0 0 0\r\nv 1 0 0\rv 0 1 0\n\rf 1 2 3\r\n"));
  EXPECT_EQ(mixed.num_faces(), 1u);
  const std::string p = dir.write("bad.obj", "v 0 0 0\rv 1 0 0\r\rv 0 x 0\r");
  EXPECT_EQ(error_of([&] { read_obj(p); }), p + ": line 4: expected a number for coordinate y of vertex 3, got 'x'");
}

TEST(TextLineEnds, PlyEveryFormatWithEveryLineEnd) {
  TempDir dir;
  const PolyMesh pm;
  for (Fmt fmt : {Fmt::Ascii, Fmt::LE, Fmt::BE})
    for (const char* end : {"\r\n", "\r"}) {
      SCOPED_TRACE(std::string(fmt_name(fmt)) + (end[1] ? " CRLF" : " CR"));
      PlyOptions o;
      o.fmt = fmt;
      o.coord = "double";
      o.extras = true;
      std::string file = make_ply(pm, o);
      const std::size_t data = file.find("end_header\n") + 11;
      // binary data stays as it is; ascii data lines take the same line ends
      file = with_line_ends(file.substr(0, data), end) +
             (fmt == Fmt::Ascii ? with_line_ends(file.substr(data), end) : file.substr(data));
      const std::string p = dir.write("e.ply", file);
      expect_poly_mesh(read_ply(p), pm, p);
    }
  // ascii: line numbers count lone CRs
  const std::string p = dir.write("bad.ply", with_line_ends(kAsciiHeader + "0 0 0\n1 0 0\n0 q 0\n", "\r"));
  EXPECT_EQ(error_of([&] { read_ply(p); }), p + ": line 12: expected a number for property 'y' of vertex 2, got 'q'");
}

TEST(TextLineEnds, PlyBinaryAfterLoneCrHeaderMayStartWithLf) {
  // A binary file whose header lines end in a lone CR, and whose first data byte is 0x0A:
  // the data starts right after "end_header\r" (its first line says lone CRs), not a byte later.
  TempDir dir;
  for (bool big : {false, true}) {
    const std::string header =
        std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
        " 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const double x0 = std::bit_cast<double>(big ? std::uint64_t{0x0A00000000000000} : std::uint64_t{0x3FF000000000000A});
    Bytes b;
    b.big = big;
    b.put<double>(x0).put<double>(0).put<double>(0);
    b.put<double>(1).put<double>(0).put<double>(0).put<double>(0).put<double>(1).put<double>(0);
    b.put<std::uint8_t>(3).put<std::int32_t>(0).put<std::int32_t>(1).put<std::int32_t>(2);
    ASSERT_EQ(b.s[0], '\n');
    const TriMesh m = read_ply(dir.write("cr.ply", with_line_ends(header, "\r") + b.s));
    EXPECT_EQ(m.vertices(0, 0), x0);
    EXPECT_EQ(m.vertices(2, 1), 1.0);
    EXPECT_EQ(m.faces, (std::vector<Triangle>{{0, 1, 2}}));
    // with CRLF header lines, the same bytes after "end_header\r\n" are data
    const TriMesh crlf = read_ply(dir.write("crlf.ply", with_line_ends(header, "\r\n") + b.s));
    EXPECT_EQ(crlf.vertices, m.vertices);
    EXPECT_EQ(read_ply(dir.write("lf.ply", header + b.s)).vertices, m.vertices);
  }
}

TEST(ObjReader, VertexLineValues) {
  TempDir dir;
  auto read = [&](const std::string& v_line) {
    return read_obj(dir.write("v.obj", "v 0 0 0\nv 0 1 0\n" + v_line + "\nf 1 2 3\n"));
  };
  // x y z; x y z w; x y z r g b; a comment after any of them
  for (const char* ok : {"v 1 2 3", "v 1 2 3 1", "v 1 2 3 0.5", "v 1 2 3 0.1 0.2 0.3", "v 1 2 3 # note",
                         "v 1 2 3 1 #note", "v\t1\t2\t3\t255 0 12\t# rgb"})
    EXPECT_EQ(read(ok).vertices.point(2), Vec3(1, 2, 3)) << ok;
  const std::string p = dir.file("v.obj");
  auto err = [&](const std::string& v_line) { return error_of([&] { read(v_line); }); };
  EXPECT_EQ(err("v 1 2 3 4 5"), p + ": line 3: vertex 3: expected x y z, x y z w or x y z r g b, got 5 values");
  EXPECT_EQ(err("v 1 2 3 4 5 6 7"), p + ": line 3: vertex 3: expected x y z, x y z w or x y z r g b, got 7 values");
  EXPECT_EQ(err("v 1 2 3 junk"), p + ": line 3: expected a number for value 4 of vertex 3, got 'junk'");
  EXPECT_EQ(err("v 1 2 3 1 2 x"), p + ": line 3: expected a number for value 6 of vertex 3, got 'x'");
  EXPECT_EQ(err("v 1 2 3 nan"), p + ": line 3: value 4 of vertex 3 is not finite ('nan')");
  EXPECT_EQ(err("v 1 2 3#x"), p + ": line 3: expected a number for coordinate z of vertex 3, got '3#x'");
  // a long offending token is quoted by its first 40 characters only
  const std::string junk(5000, 'j');
  EXPECT_EQ(err("v 1 2 " + junk), p + ": line 3: expected a number for coordinate z of vertex 3, got '" +
                                      junk.substr(0, 40) + "...'");
}
