#pragma once
/// @file Mesh files: OBJ and PLY readers and writers (frame sequences: frame_sequence.h).
/// Every reader throws mccd::Error naming the file, the line or element, and what was
/// expected; a writer that fails leaves no partial file behind.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <mccd/geometry/frame_sequence.h>
#include <mccd/geometry/mesh.h>

namespace mccd {

/// Reads an OBJ or PLY file, chosen by extension (.obj / .ply, case-insensitive).
TriMesh read_mesh(const std::string& path);
/// Wavefront OBJ: `v` and `f` lines (polygons fan-triangulated, `a/b/c`, `a//c`, `a/b`
/// forms, negative indices); other statements ignored. A `v` line holds x y z, optionally
/// followed by a weight w (used by rational curves and surfaces only) or by r g b vertex
/// colours (a common extension); those must be finite numbers and are ignored; any other
/// count of values is refused, as is anything after them but a `#` comment. Lines may end in
/// "\n", "\r\n" or "\r".
TriMesh read_obj(const std::string& path);
/// PLY: ascii, binary_little_endian, binary_big_endian; float or double x, y, z; any
/// integer list type for faces; other properties and elements skipped. Header lines (and
/// ascii data lines) may end in "\n", "\r\n" or "\r"; a binary file's data starts right
/// after "end_header" and the line end its first line uses.
TriMesh read_ply(const std::string& path);

/// Optional per-face colour for the PLY writer (r, g, b in 0..255).
using FaceColors = std::vector<std::array<std::uint8_t, 3>>;
/// Writes a binary little-endian PLY (double coordinates, int indices), with per-face colour
/// when `colors` is non-empty (one per face). Written to a temporary, then renamed.
void write_ply(const std::string& path, const TriMesh& mesh, const FaceColors& colors = {});
/// Writes an OBJ with full double precision. Written to a temporary, then renamed.
void write_obj(const std::string& path, const TriMesh& mesh);

}  // namespace mccd
