// Frame sequences: printf-style patterns, and frames checked against the first one.
#include <mccd/geometry/frame_sequence.h>

#include <cctype>
#include <filesystem>

#include <mccd/geometry/error.h>
#include <mccd/geometry/mesh_io.h>

namespace mccd {

namespace fs = std::filesystem;

namespace {

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
  // appended piece by piece: `"(" + std::string&&` inserts at the front, where GCC 12 warns
  // of an overlapping copy that cannot happen (-Wrestrict, GCC bug 105329)
  std::string s = "(";
  for (int k = 0; k < 3; ++k) s.append(k ? ", " : "").append(std::to_string(t[k]));
  return s.append(")");
}

}  // namespace

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
