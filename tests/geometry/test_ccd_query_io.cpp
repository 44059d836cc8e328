// Reader of the rational CCD query files.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <tuple>

#include <mccd/geometry/error.h>
#include <mccd/geometry/query_io.h>

using namespace mccd;

namespace {
std::string write_temp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path.string();
}
std::string error_of(const std::string& path) {
  try {
    read_query_csv(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}
std::string rows(int n, const std::string& row) {
  std::string s;
  for (int i = 0; i < n; ++i) s += row + "\n";
  return s;
}
}  // namespace

TEST(CcdQueryIo, ExactConversion) {
  EXPECT_EQ(rational_to_double("1", "2"), 0.5);
  EXPECT_EQ(rational_to_double("-3", "4"), -0.75);
  EXPECT_EQ(rational_to_double("0", "1"), 0.0);
  // 2^-100 with a 31-digit denominator; a numerator with 17 digits.
  EXPECT_EQ(rational_to_double("1", "1267650600228229401496703205376"), std::ldexp(1.0, -100));
  EXPECT_EQ(rational_to_double("6004799503160661", "36028797018963968"), 6004799503160661.0 / 36028797018963968.0);
  // A long numerator with trailing zero bits: 2^70 * 3 / 2^71.
  EXPECT_EQ(rational_to_double("3541774862152233910272", "2361183241434822606848"), 1.5);
  EXPECT_THROW(rational_to_double("1", "3"), Error);
  EXPECT_THROW(rational_to_double("1", "0"), Error);
  EXPECT_THROW(rational_to_double("9007199254740993", "1"), Error);  // 2^53 + 1: not a double
  EXPECT_THROW(rational_to_double("x", "1"), Error);
}

TEST(CcdQueryIo, ReadsQueriesAndTruth) {
  const std::string p = write_temp("mccd_q_ok.csv", rows(8, "1,2,-1,4,0,1,1") + rows(8, "3,8,1,1,5,16,0"));
  const auto qs = read_query_csv(p);
  ASSERT_EQ(qs.size(), 2u);
  EXPECT_EQ(qs[0].truth, 1);
  EXPECT_EQ(qs[1].truth, 0);
  EXPECT_EQ(qs[0].points.start[0], Vec3(0.5, -0.25, 0));
  EXPECT_EQ(qs[1].points.end[3], Vec3(0.375, 1, 0.3125));
  const std::string p6 = write_temp("mccd_q_6.csv", rows(8, "1,2,-1,4,0,1"));
  EXPECT_EQ(read_query_csv(p6).at(0).truth, -1);
}

TEST(CcdQueryIo, MalformedInputNamesFileAndLine) {
  const std::string bad_den = write_temp("mccd_q_den.csv", rows(3, "1,2,1,2,1,2,0") + "1,3,1,2,1,2,0\n");
  EXPECT_NE(error_of(bad_den).find("mccd_q_den.csv:4:"), std::string::npos) << error_of(bad_den);
  EXPECT_NE(error_of(bad_den).find("power of two"), std::string::npos);
  const std::string cols = write_temp("mccd_q_cols.csv", "1,2,1,2\n");
  EXPECT_NE(error_of(cols).find("mccd_q_cols.csv:1:"), std::string::npos) << error_of(cols);
  const std::string count = write_temp("mccd_q_count.csv", rows(5, "1,2,1,2,1,2,0"));
  EXPECT_NE(error_of(count).find("multiple of 8"), std::string::npos) << error_of(count);
  const std::string truth = write_temp("mccd_q_truth.csv", rows(1, "1,2,1,2,1,2,0") + rows(7, "1,2,1,2,1,2,1"));
  EXPECT_NE(error_of(truth).find("mccd_q_truth.csv:2:"), std::string::npos) << error_of(truth);
  const std::string mixed = write_temp("mccd_q_mixed.csv", rows(1, "1,2,1,2,1,2,0") + rows(7, "1,2,1,2,1,2"));
  EXPECT_NE(error_of(mixed).find(":2:"), std::string::npos) << error_of(mixed);
  EXPECT_NE(error_of("/nonexistent/q.csv").find("cannot open"), std::string::npos);
}

namespace {
/// 2^k in decimal.
std::string power_of_two(int k) {
  std::string digits = "1";  // least significant first
  for (int i = 0; i < k; ++i) {
    int carry = 0;
    for (char& c : digits) {
      const int d = (c - '0') * 2 + carry;
      c = static_cast<char>('0' + d % 10);
      carry = d / 10;
    }
    if (carry) digits += static_cast<char>('0' + carry);
  }
  return std::string(digits.rbegin(), digits.rend());
}
}  // namespace

TEST(CcdQueryIo, LongestExactFormsAreAccepted) {
  // the smallest subnormal, 1 / 2^1074 (a 324-digit denominator), and the largest double as an
  // integer (309 digits)
  const std::string d1074 = power_of_two(1074);
  ASSERT_EQ(d1074.size(), 324u);
  EXPECT_EQ(rational_to_double("1", d1074), std::numeric_limits<double>::denorm_min());
  EXPECT_EQ(rational_to_double("-3", d1074), -3 * std::numeric_limits<double>::denorm_min());
  const std::string max = "179769313486231570814527423731704356798070567525844996598917476803157260780028538760589558632766878"
                          "171540458953514382464234321326889464182768467546703537516986049910576551282076245490090389328944075"
                          "868508455133942304583236903222948165808559332123348274797826204144723168738177180919299881250404026"
                          "184124858368";
  ASSERT_EQ(max.size(), 309u);
  EXPECT_EQ(rational_to_double(max, "1"), std::numeric_limits<double>::max());
  // leading zeros count: kMaxRationalDigits digits are accepted, one more is refused
  EXPECT_EQ(rational_to_double(std::string(kMaxRationalDigits - 1, '0') + "5", "+0002"), 2.5);
  EXPECT_THROW(rational_to_double(std::string(kMaxRationalDigits, '0') + "5", "2"), Error);
  EXPECT_THROW(rational_to_double(power_of_two(1075), "1"), Error);  // out of range
  EXPECT_THROW(rational_to_double("1", power_of_two(1075)), Error);  // below the smallest subnormal
}

TEST(CcdQueryIo, OverlongIntegersAreRefusedAtOnce) {
  // issue 12, defect 1: a 100,000-digit integer took 81 s to refuse (quadratic conversion)
  const std::string huge(100000, '7');
  for (const auto& [num, den, what] : {std::tuple{huge, std::string("1"), "numerator"},
                                       std::tuple{std::string("1"), huge, "denominator"},
                                       std::tuple{"-" + huge, std::string("2"), "numerator"}}) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string message;
    try {
      rational_to_double(num, den);
    } catch (const Error& e) {
      message = e.what();
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_LT(seconds, 0.5) << what;  // microseconds in fact; generous for sanitizers and load
    const std::string& field = std::string(what) == "numerator" ? num : den;
    EXPECT_EQ(message, std::string(what) + " '" + field.substr(0, 40) + "...' has " +
                           std::to_string(field.size() - (field[0] == '-' ? 1 : 0)) + " digits (at most 400 are accepted)");
  }
  // in a file: refused naming the line, quoting a short prefix only
  const std::string p = write_temp("mccd_q_long.csv", rows(8, "1,2,1,2,1,2") + huge + ",1,1,1,1,1\n");
  const std::string e = error_of(p);
  EXPECT_NE(e.find("mccd_q_long.csv:9: column 1/2: numerator '7777"), std::string::npos) << e.substr(0, 200);
  EXPECT_LT(e.size(), 250u + p.size());
}

TEST(CcdQueryIo, ErrorMessagesQuoteShortPrefixes) {
  const std::string long_field(3000, '9');
  for (const std::string& row : {"1," + long_field + "3,1,1,1,1", "1,3" + long_field + ",1,1,1,1",
                                 "x" + long_field + ",1,1,1,1,1", "1,1,1,1,1,1,2" + long_field,
                                 "1," + std::string(300, '0') + "3,1,1,1,1"}) {
    const std::string p = write_temp("mccd_q_quote.csv", rows(8, row));
    const std::string e = error_of(p);
    EXPECT_NE(e.find("mccd_q_quote.csv:1: "), std::string::npos) << e.substr(0, 200);
    EXPECT_LT(e.size(), 250u + p.size()) << e.substr(0, 200);
  }
  // a row with very many columns is refused without splitting all of it
  const std::string p = write_temp("mccd_q_cols_many.csv", "1" + std::string(100000, ',') + "\n");
  EXPECT_NE(error_of(p).find("expected 6 or 7 comma-separated columns, got 100001"), std::string::npos) << error_of(p);
}

TEST(CcdQueryIo, EveryLineEnd) {
  const std::string lf = rows(8, "1,2,-1,4,0,1,1") + rows(8, "3,8,1,1,5,16,0");
  const auto expected = read_query_csv(write_temp("mccd_q_lf.csv", lf));
  ASSERT_EQ(expected.size(), 2u);
  for (const std::string end : {"\r\n", "\r"}) {
    std::string text;
    for (char c : lf) c == '\n' ? text += end : text += c;
    const auto got = read_query_csv(write_temp("mccd_q_end.csv", text));
    ASSERT_EQ(got.size(), 2u) << (end.size() == 1 ? "CR" : "CRLF");
    for (int q = 0; q < 2; ++q) {
      EXPECT_EQ(got[q].truth, expected[q].truth);
      for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(got[q].points.start[i], expected[q].points.start[i]);
        EXPECT_EQ(got[q].points.end[i], expected[q].points.end[i]);
      }
    }
  }
  // line numbers in messages count lone CRs
  const std::string bad = write_temp("mccd_q_cr_bad.csv", "1,2,1,2,1,2,0\r1,2,1,2,1,3,0\r");
  EXPECT_NE(error_of(bad).find("mccd_q_cr_bad.csv:2: column 5/6"), std::string::npos) << error_of(bad);
}
