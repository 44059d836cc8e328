#include <mccd/geometry/atomic_file.h>

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include <mccd/geometry/error.h>

namespace mccd {

namespace fs = std::filesystem;

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  static std::atomic<unsigned> counter{0};
  const fs::path target(path_);
  if (target.filename().empty()) throw Error(path_ + ": cannot write: not a file name");
  // appended, not `"." + std::string&&`: that inserts at the front, where GCC 12 warns of an
  // overlapping copy that cannot happen (-Wrestrict, GCC bug 105329)
  std::string name = std::string(".").append(target.filename().string());
  name.append(".tmp").append(std::to_string(::getpid())).append("_").append(std::to_string(counter++));
  fs::path tmp = target;
  tmp.replace_filename(name);
  tmp_ = tmp.string();
  file_ = std::fopen(tmp_.c_str(), "wb");
  if (!file_) throw Error(path_ + ": cannot write: " + std::strerror(errno));
}

AtomicFile::~AtomicFile() { abandon(); }

void AtomicFile::write(std::string_view bytes) {
  if (!file_) throw Error(path_ + ": cannot write: the file is already closed");
  if (bytes.empty()) return;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    const int err = errno;
    abandon();
    throw Error(path_ + ": cannot write: " + std::strerror(err));
  }
}

void AtomicFile::flush() {
  if (file_ && std::fflush(file_) != 0) {
    const int err = errno;
    abandon();
    throw Error(path_ + ": cannot write: " + std::strerror(err));
  }
}

void AtomicFile::commit() {
  if (!file_) throw Error(path_ + ": cannot write: the file is already closed");
  const bool flushed = std::fflush(file_) == 0 && !std::ferror(file_);
  int err = errno;
  const bool closed = std::fclose(file_) == 0;
  if (!closed && flushed) err = errno;
  file_ = nullptr;
  if (!flushed || !closed) {
    abandon();
    throw Error(path_ + ": cannot write: " + std::strerror(err));
  }
  std::error_code ec;
  fs::rename(tmp_, path_, ec);
  if (ec) {
    abandon();
    throw Error(path_ + ": cannot write: " + ec.message());
  }
  committed_ = true;
}

void AtomicFile::abandon() noexcept {
  if (file_) {
    std::fclose(file_);
    file_ = nullptr;
  }
  if (!committed_ && !tmp_.empty()) {
    std::error_code ec;
    fs::remove(tmp_, ec);
    tmp_.clear();
  }
}

void write_atomically(const std::string& path, std::string_view bytes) {
  AtomicFile f(path);
  f.write(bytes);
  f.commit();
}

}  // namespace mccd
