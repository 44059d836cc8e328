// Exact reader of the rational CCD query CSV files (see query_io.h).
#include <mccd/geometry/query_io.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <string_view>

#include <mccd/geometry/error.h>

namespace mccd {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// An unsigned decimal integer of any length, reduced to its binary form: the value equals
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

// Parses the digits (no sign). Fast path for up to 19 digits; otherwise repeated halving of
// the decimal string (quadratic, only for unusually long integers).
BigDecimal parse_unsigned(std::string_view s) {
  BigDecimal out;
  if (s.size() <= 19) {
    std::uint64_t v = 0;
    std::from_chars(s.data(), s.data() + s.size(), v);
    out.mantissa = v;
    return out;
  }
  std::string digits(s);
  // Bits from least significant upwards.
  std::vector<bool> bits;
  auto is_zero = [&] {
    for (char c : digits)
      if (c != '0') return false;
    return true;
  };
  while (!is_zero()) {
    bits.push_back(((digits.back() - '0') & 1) != 0);
    int carry = 0;
    for (char& c : digits) {
      const int cur = carry * 10 + (c - '0');
      c = static_cast<char>('0' + cur / 2);
      carry = cur % 2;
    }
  }
  // Strip trailing zero bits into the shift, keep the top 64 bits.
  std::size_t low = 0;
  while (low < bits.size() && !bits[low]) ++low;
  if (low == bits.size()) return out;
  const std::size_t width = bits.size() - low;
  std::size_t take_from = low;
  if (width > 64) {
    take_from = bits.size() - 64;
    out.exact = false;
  }
  for (std::size_t i = bits.size(); i-- > take_from;) out.mantissa = (out.mantissa << 1) | (bits[i] ? 1u : 0u);
  out.shift = static_cast<int>(take_from);
  return out;
}

}  // namespace

double rational_to_double(const std::string& numerator, const std::string& denominator) {
  std::string_view num = trim(numerator), den = trim(denominator);
  bool negative = false;
  if (!num.empty() && (num.front() == '-' || num.front() == '+')) {
    negative = num.front() == '-';
    num.remove_prefix(1);
  }
  if (!all_digits(num)) throw Error("numerator '" + std::string(trim(numerator)) + "' is not an integer");
  if (!den.empty() && den.front() == '+') den.remove_prefix(1);
  if (!all_digits(den)) throw Error("denominator '" + std::string(trim(denominator)) + "' is not a positive integer");
  const BigDecimal d = parse_unsigned(den);
  if (d.mantissa == 0) throw Error("denominator is zero");
  if (!d.exact || (d.mantissa & (d.mantissa - 1)) != 0)
    throw Error("denominator " + std::string(den) + " is not a power of two");
  int den_exp = d.shift;
  for (std::uint64_t m = d.mantissa; m > 1; m >>= 1) ++den_exp;

  BigDecimal n = parse_unsigned(num);
  if (n.mantissa == 0) return negative ? -0.0 : 0.0;
  // Normalise: odd mantissa.
  while ((n.mantissa & 1u) == 0) {
    n.mantissa >>= 1;
    ++n.shift;
  }
  if (!n.exact || n.mantissa >= (std::uint64_t{1} << 53))
    throw Error(std::string(negative ? "-" : "") + std::string(num) + "/" + std::string(den) +
                " is not exactly representable as a double (more than 53 significant bits)");
  const double m = static_cast<double>(n.mantissa);  // exact: < 2^53
  const int e = n.shift - den_exp;
  const double v = std::ldexp(m, e);
  if (!std::isfinite(v) || std::ldexp(v, -e) != m)
    throw Error(std::string(negative ? "-" : "") + std::string(num) + "/" + std::string(den) +
                " is out of the range of doubles");
  return negative ? -v : v;
}

std::vector<CcdQuery> read_query_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot open");
  std::vector<CcdQuery> out;
  std::string line;
  std::size_t line_no = 0, row = 0;
  int columns = 0;
  CcdQuery current;
  for (int i = 0; i < 4; ++i) current.points.start[i] = current.points.end[i] = Vec3::Zero();
  std::size_t query_first_line = 0;
  std::vector<std::string> fields;
  while (std::getline(in, line)) {
    ++line_no;
    std::string_view lv = trim(line);
    if (lv.empty()) continue;
    fields.clear();
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = lv.find(',', start);
      fields.emplace_back(trim(lv.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    const int cols = static_cast<int>(fields.size());
    if (cols != 6 && cols != 7)
      throw Error(where + "expected 6 or 7 comma-separated columns, got " + std::to_string(cols));
    if (columns == 0) columns = cols;
    if (cols != columns)
      throw Error(where + "row has " + std::to_string(cols) + " columns, earlier rows have " + std::to_string(columns));
    Vec3 point;
    for (int k = 0; k < 3; ++k) {
      try {
        point[k] = rational_to_double(fields[2 * k], fields[2 * k + 1]);
      } catch (const Error& e) {
        throw Error(where + "column " + std::to_string(2 * k + 1) + "/" + std::to_string(2 * k + 2) + ": " + e.what());
      }
    }
    const std::size_t slot = row % 8;
    if (slot == 0) {
      current.truth = -1;
      query_first_line = line_no;
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
        throw Error(where + "truth column must be 0 or 1, got '" + fields[6] + "'");
      if (slot == 0)
        current.truth = truth;
      else if (truth != current.truth)
        throw Error(where + "truth " + std::to_string(truth) + " differs from the query's first row (line " +
                    std::to_string(query_first_line) + ")");
    }
    if (slot == 7) out.push_back(current);
    ++row;
  }
  if (row % 8 != 0)
    throw Error(path + ":" + std::to_string(line_no) + ": file ends inside a query (" + std::to_string(row) +
                " rows, not a multiple of 8)");
  return out;
}

}  // namespace mccd
