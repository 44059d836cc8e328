#pragma once
/// @file Files that appear complete or not at all: every writer in the tree (meshes, contact
/// lists, statistics, benchmark tables) writes to a temporary beside the target and renames it
/// over the target at the end. On failure, or when the writer is destroyed without commit(),
/// the temporary is removed and the target is left as it was.
#include <cstdio>
#include <string>
#include <string_view>

namespace mccd {

class AtomicFile {
 public:
  /// Opens a temporary ".NAME.tmpPID_N" in the target's folder. Throws mccd::Error naming the
  /// target when it cannot be created.
  explicit AtomicFile(std::string path);
  /// Removes the temporary unless commit() succeeded.
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// Appends bytes; throws mccd::Error naming the target on a write error.
  void write(std::string_view bytes);
  /// Pushes buffered bytes to the temporary (a long run can be followed with `tail`).
  void flush();
  /// Closes the temporary and renames it over the target. Throws mccd::Error on failure (the
  /// temporary is then removed).
  void commit();
  /// Removes the temporary now; the target is left as it was. Safe to call twice.
  void abandon() noexcept;

  const std::string& path() const { return path_; }
  const std::string& temp_path() const { return tmp_; }
  bool committed() const { return committed_; }

 private:
  std::string path_, tmp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

/// Writes `bytes` to `path` through an AtomicFile.
void write_atomically(const std::string& path, std::string_view bytes);

}  // namespace mccd
