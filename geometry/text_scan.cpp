#include <mccd/geometry/text_scan.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include <mccd/geometry/error.h>
#include <mccd/geometry/large_allocator.h>

namespace mccd::detail {

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

/// Whole file as bytes. Throws "cannot open" naming the file and the reason.
std::string read_all(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(path + ": cannot open: is a directory");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error(path + ": cannot open: " + std::strerror(errno));
  std::string data;
  char buf[1 << 16];
  if (std::fseek(f, 0, SEEK_END) == 0) {
    const long size = std::ftell(f);
    if (size > 0) {
      data.reserve(static_cast<std::size_t>(size));
      detail::populate_pages(data.data(), static_cast<std::size_t>(size));  // megabytes, about to be written
    }
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

void check_repeated(const Triangle& t, const std::string& where) {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
    throw Error(where + ": repeated vertex index (" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " +
                std::to_string(t[2]) + ")");
}

}  // namespace mccd::detail
