// Exact reader of the rational CCD query CSV files (see query_io.h).
#include <mccd/geometry/query_io.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string_view>

#include <mccd/geometry/error.h>
#include <mccd/geometry/parsers.h>
#include <mccd/geometry/text_scan.h>

namespace mccd {
namespace {

using detail::quote_tok;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// An unsigned decimal integer, reduced to its binary form: the value equals
// `mantissa * 2^shift` where `mantissa` keeps at most 64 significant bits; `exact` is false
// when bits were lost (only possible for integers with more than 64 significant bits).
struct BigDecimal {
  std::uint64_t mantissa = 0;
  int shift = 0;
  bool exact = true;
};

bool all_digits(std::string_view s) {
  if (s.empty()) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

// Parses at most kMaxRationalDigits digits (no sign). Fast path for up to 19 digits; otherwise the
// digits go into 32-bit binary limbs, nine at a time (at most 45 chunks of 42 limbs).
BigDecimal parse_unsigned(std::string_view s) {
  BigDecimal out;
  if (s.size() <= 19) {
    std::uint64_t v = 0;
    std::from_chars(s.data(), s.data() + s.size(), v);
    out.mantissa = v;
    return out;
  }
  std::vector<std::uint32_t> limbs;  // least significant first
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = std::min<std::size_t>(9, s.size() - i);
    std::uint32_t chunk = 0, scale = 1;
    for (std::size_t k = 0; k < n; ++k, ++i) {
      chunk = chunk * 10 + static_cast<std::uint32_t>(s[i] - '0');
      scale *= 10;
    }
    std::uint64_t carry = chunk;
    for (std::uint32_t& l : limbs) {
      const std::uint64_t cur = std::uint64_t{l} * scale + carry;  // < 2^62
      l = static_cast<std::uint32_t>(cur);
      carry = cur >> 32;
    }
    if (carry) limbs.push_back(static_cast<std::uint32_t>(carry));
  }
  auto bit = [&](std::size_t b) { return (limbs[b / 32] >> (b % 32)) & 1u; };
  const std::size_t width = 32 * limbs.size();
  std::size_t low = 0;
  while (low < width && !bit(low)) ++low;
  if (low == width) return out;  // zero
  std::size_t high = width - 1;
  while (!bit(high)) --high;
  std::size_t take_from = low;
  if (high - low + 1 > 64) {
    take_from = high - 63;
    out.exact = false;
  }
  for (std::size_t b = high + 1; b-- > take_from;) out.mantissa = (out.mantissa << 1) | bit(b);
  out.shift = static_cast<int>(take_from);
  return out;
}

// Refuses an integer field that is not all digits or longer than kMaxRationalDigits (before
// any conversion work, which is quadratic in the length).
void check_integer(std::string_view digits, std::string_view field, const char* what, const char* expected) {
  if (!all_digits(digits)) throw Error(std::string(what) + " " + quote_tok(field) + " is not " + expected);
  if (digits.size() > kMaxRationalDigits)
    throw Error(std::string(what) + " " + quote_tok(field) + " has " + std::to_string(digits.size()) +
                " digits (at most " + std::to_string(kMaxRationalDigits) + " are accepted)");
}

double to_double(std::string_view numerator, std::string_view denominator) {
  std::string_view num = trim(numerator), den = trim(denominator);
  const std::string_view num_field = num, den_field = den;
  bool negative = false;
  if (!num.empty() && (num.front() == '-' || num.front() == '+')) {
    negative = num.front() == '-';
    num.remove_prefix(1);
  }
  check_integer(num, num_field, "numerator", "an integer");
  if (!den.empty() && den.front() == '+') den.remove_prefix(1);
  check_integer(den, den_field, "denominator", "a positive integer");
  const BigDecimal d = parse_unsigned(den);
  if (d.mantissa == 0) throw Error("denominator is zero");
  if (!d.exact || (d.mantissa & (d.mantissa - 1)) != 0)
    throw Error("denominator " + quote_tok(den) + " is not a power of two");
  int den_exp = d.shift;
  for (std::uint64_t m = d.mantissa; m > 1; m >>= 1) ++den_exp;

  BigDecimal n = parse_unsigned(num);
  if (n.mantissa == 0) return negative ? -0.0 : 0.0;
  // Normalise: odd mantissa.
  while ((n.mantissa & 1u) == 0) {
    n.mantissa >>= 1;
    ++n.shift;
  }
  const std::string value = quote_tok(num_field) + "/" + quote_tok(den);
  if (!n.exact || n.mantissa >= (std::uint64_t{1} << 53))
    throw Error(value + " is not exactly representable as a double (more than 53 significant bits)");
  const double m = static_cast<double>(n.mantissa);  // exact: < 2^53
  const int e = n.shift - den_exp;
  const double v = std::ldexp(m, e);
  if (!std::isfinite(v) || std::ldexp(v, -e) != m) throw Error(value + " is out of the range of doubles");
  return negative ? -v : v;
}

}  // namespace

double rational_to_double(const std::string& numerator, const std::string& denominator) {
  return to_double(numerator, denominator);
}

namespace detail {

std::vector<CcdQuery> parse_query_csv(const std::string& path, std::string_view text) {
  std::vector<CcdQuery> out;
  LineReader lines(text);
  std::string_view line;
  std::size_t row = 0;
  int columns = 0;
  CcdQuery current;
  for (int i = 0; i < 4; ++i) current.points.start[i] = current.points.end[i] = Vec3::Zero();
  std::size_t query_first_line = 0;
  std::vector<std::string_view> fields;
  while (lines.next(line)) {
    const std::string_view lv = trim(line);
    if (lv.empty()) continue;
    auto where = [&] { return path + ":" + std::to_string(lines.line_no()) + ": "; };
    fields.clear();
    for (std::size_t start = 0;;) {
      const std::size_t comma = lv.find(',', start);
      if (fields.size() == 7)
        throw Error(where() + "expected 6 or 7 comma-separated columns, got " +
                    std::to_string(8 + std::count(lv.begin() + static_cast<std::ptrdiff_t>(start), lv.end(), ',')));
      fields.push_back(trim(lv.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    const int cols = static_cast<int>(fields.size());
    if (cols != 6 && cols != 7)
      throw Error(where() + "expected 6 or 7 comma-separated columns, got " + std::to_string(cols));
    if (columns == 0) columns = cols;
    if (cols != columns)
      throw Error(where() + "row has " + std::to_string(cols) + " columns, earlier rows have " + std::to_string(columns));
    Vec3 point;
    for (int k = 0; k < 3; ++k) {
      try {
        point[k] = to_double(fields[2 * k], fields[2 * k + 1]);
      } catch (const Error& e) {
        throw Error(where() + "column " + std::to_string(2 * k + 1) + "/" + std::to_string(2 * k + 2) + ": " + e.what());
      }
    }
    const std::size_t slot = row % 8;
    if (slot == 0) {
      current.truth = -1;
      query_first_line = lines.line_no();
    }
    if (slot < 4)
      current.points.start[slot] = point;
    else
      current.points.end[slot - 4] = point;
    if (cols == 7) {
      int truth;
      if (fields[6] == "0")
        truth = 0;
      else if (fields[6] == "1")
        truth = 1;
      else
        throw Error(where() + "truth column must be 0 or 1, got " + quote_tok(fields[6]));
      if (slot == 0)
        current.truth = truth;
      else if (truth != current.truth)
        throw Error(where() + "truth " + std::to_string(truth) + " differs from the query's first row (line " +
                    std::to_string(query_first_line) + ")");
    }
    if (slot == 7) out.push_back(current);
    ++row;
  }
  if (row % 8 != 0)
    throw Error(path + ":" + std::to_string(lines.line_no()) + ": file ends inside a query (" + std::to_string(row) +
                " rows, not a multiple of 8)");
  return out;
}

}  // namespace detail

std::vector<CcdQuery> read_query_csv(const std::string& path) {
  const std::string text = detail::read_all(path);
  return detail::parse_query_csv(path, text);
}

}  // namespace mccd
