#pragma once
/// @file Frame sequences: one mesh file per frame, same triangles, moving vertices.
#include <string>
#include <vector>

#include <mccd/geometry/mesh.h>

namespace mccd {

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
