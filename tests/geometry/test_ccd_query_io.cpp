// Reader of the rational CCD query files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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
