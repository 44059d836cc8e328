#pragma once
/// @file Internal: what every text reader in the tree shares. Whole-file reads, lines (ended by
/// "\n", "\r\n" or a lone "\r"), whitespace tokens, exact number parsing, and short quotes of
/// offending tokens for error messages.
#include <charconv>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>

#include <mccd/geometry/mesh.h>

namespace mccd::detail {

/// A token quoted for an error message: at most 40 characters, then "...".
std::string quote_tok(std::string_view s);
std::string lower(std::string s);
inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
/// Whole file as bytes. Throws mccd::Error "cannot open" / "cannot read" naming the file and
/// the reason.
std::string read_all(const std::string& path);
/// Only whitespace, line ends and NUL bytes.
bool all_space(std::string_view s);
/// Throws mccd::Error "<where>: repeated vertex index (a, b, c)" when a corner repeats.
void check_repeated(const Triangle& t, const std::string& where);

/// Splits text into lines, tracking line numbers (1-based). A line ends at "\n", "\r\n" or
/// a lone "\r" (old Mac files); the ending is not part of the line.
class LineReader {
 public:
  explicit LineReader(std::string_view text, std::size_t first_line = 1) : text_(text), next_line_(first_line) {}
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = text_.find_first_of("\r\n", pos_);
    const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
    line = text_.substr(pos_, stop - pos_);
    if (end == std::string_view::npos)
      pos_ = text_.size();
    else if (text_[end] == '\r' && end + 1 < text_.size() && text_[end + 1] == '\n')
      pos_ = end + 2;
    else
      pos_ = end + 1;
    line_no_ = next_line_++;
    return true;
  }
  std::size_t line_no() const { return line_no_; }
  /// Offset of the first byte after the last line returned.
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
inline bool parse_double(std::string_view tok, double& out) { return parse_number(tok, out); }
inline bool parse_int(std::string_view tok, std::int64_t& out) { return parse_number(tok, out); }

}  // namespace mccd::detail
