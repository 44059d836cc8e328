#include "time_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace mccd::cli {

namespace {

/// t (below 1e-3) with 3 significant digits in scientific notation, without trailing zeros,
/// padding zeros or plus sign: "7.49e-6", "2.5e-5", "1e-300".
std::string scientific(double t) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2e", t);
  const std::string s = buf;
  const std::size_t e = s.find('e');
  std::string mantissa = s.substr(0, e), exponent = s.substr(e + 1);
  mantissa.erase(mantissa.find_last_not_of('0') + 1);
  if (mantissa.back() == '.') mantissa.pop_back();
  const bool negative = exponent[0] == '-';
  exponent.erase(0, 1);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return mantissa + "e" + (negative ? "-" : "") + exponent;
}

}  // namespace

std::string impact_text(double v) {
  char buf[64];
  if (std::isinf(v) && v > 0) return "-";
  if (!std::isfinite(v) || v < 0) {
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }
  const double k = std::floor(v), t = v - k;
  std::snprintf(buf, sizeof buf, "%.0f", k);
  const std::string whole = buf;
  if (t == 0) return whole;
  if (t < 1e-3) return k == 0 ? scientific(t) : whole + " + " + scientific(t);
  // 4 significant digits of t: 4, 5 or 6 decimals; more when rounding would reach frame k + 1
  int decimals = 3 - int(std::floor(std::log10(t)));
  for (;; ++decimals) {
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    if (std::floor(std::strtod(buf, nullptr)) == k || decimals >= 17) break;
  }
  std::string s = buf;
  s.erase(s.find_last_not_of('0') + 1);
  if (s.back() == '.') s.pop_back();
  return s;
}

}  // namespace mccd::cli
