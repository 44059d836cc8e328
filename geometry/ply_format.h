#pragma once
/// @file Internal: the PLY header (format, elements, properties, scalar types) and where the
/// reader finds positions and faces in it.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace mccd::detail {

enum class Scalar { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

inline bool scalar_from_name(std::string_view n, Scalar& s) {
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

inline std::size_t scalar_size(Scalar s) {
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

inline bool is_integer(Scalar s) { return s != Scalar::Float32 && s != Scalar::Float64; }

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
inline double load_double(const char* p, Scalar s, bool swap) { return load_as<double>(p, s, swap); }
inline std::int64_t load_int(const char* p, Scalar s, bool swap) { return load_as<std::int64_t>(p, s, swap); }

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

/// Where the reader finds what it needs in the elements.
struct Layout {
  int vertex_elem = -1, face_elem = -1;
  int xyz[3] = {-1, -1, -1};  // property indices in the vertex element
  int indices = -1;           // property index of vertex_indices in the face element
};

/// Parses the header (up to and including "end_header"); throws mccd::Error naming the file
/// and the line.
Header parse_ply_header(const std::string& path, std::string_view text);
/// Finds the vertex coordinates and the face index list; throws when one is missing or of the
/// wrong kind.
Layout make_layout(const std::string& path, const Header& h);

}  // namespace mccd::detail
