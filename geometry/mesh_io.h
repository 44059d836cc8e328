#pragma once
/// @file Mesh files: OBJ and PLY readers and writers, and frame sequences.
/// Every reader throws mccd::Error naming the file, the line or element, and what was
/// expected; a writer that fails leaves no partial file behind.
#include <string>
#include <vector>

#include "geometry/mesh.h"

namespace mccd {

/// Reads an OBJ or PLY file, chosen by extension (.obj / .ply, case-insensitive).
TriMesh read_mesh(const std::string& path);
/// Wavefront OBJ: `v` and `f` lines (polygons fan-triangulated, `a/b/c`, `a//c`, `a/b`
/// forms, negative indices); other statements ignored.
TriMesh read_obj(const std::string& path);
/// PLY: ascii, binary_little_endian, binary_big_endian; float or double x, y, z; any
/// integer list type for faces; other properties and elements skipped.
TriMesh read_ply(const std::string& path);

/// Optional per-face colour for the PLY writer (r, g, b in 0..255).
using FaceColors = std::vector<std::array<std::uint8_t, 3>>;
/// Writes a binary little-endian PLY (double coordinates, int indices), with per-face colour
/// when `colors` is non-empty (one per face). Written to a temporary, then renamed.
void write_ply(const std::string& path, const TriMesh& mesh, const FaceColors& colors = {});
/// Writes an OBJ with full double precision. Written to a temporary, then renamed.
void write_obj(const std::string& path, const TriMesh& mesh);

/// Expands a printf-style pattern ("frame%03d.ply") into the existing files for 0, 1, 2, ...
/// (starting at the first index that exists, among 0 and 1, and stopping at the first gap).
/// A path with no '%' is returned as is.
std::vector<std::string> expand_frame_pattern(const std::string& pattern);

/// A sequence of frames of one mesh: the triangle list of the first file, and one position
/// array per file. Every frame must have the same vertex count and the same triangle list
/// as the first; a mismatch throws naming the frame file and the first differing face.
struct FrameSequence {
  TriMesh mesh;                     ///< triangles, and the first frame's positions
  std::vector<Positions> frames;    ///< positions of every frame, the first included
  std::vector<std::string> paths;   ///< the file of each frame
};
/// Loads the given files, or the files matching one pattern when a single path contains '%'.
FrameSequence read_frames(const std::vector<std::string>& paths_or_pattern);

/// The frame files of a sequence: the given files, or those matching one pattern when a single
/// path contains '%'. Throws when there are none.
std::vector<std::string> frame_paths(const std::vector<std::string>& paths_or_pattern);
/// Reads frame `index` of a sequence from `path`: it must have the vertex count and the
/// triangle list of `first` (read from `first_path`); a mismatch throws naming the frame file
/// and the first differing face. Returns its positions.
Positions read_frame(const std::string& path, std::size_t index, const TriMesh& first, const std::string& first_path);

}  // namespace mccd
