// Ground truth of the Time-of-Impact data layout (tools/toi_truth.h): what `mccd toi-check`
// checks a step against. Accepted forms, and every refusal naming the file and the entry.
#include "toi_truth.h"

#include <gtest/gtest.h>

#include "support/errors.h"
#include <mccd/geometry/error.h>

using mccd::cli::parse_truth_pairs;
using mccd::test::error_of;

namespace {
std::string error_for(const std::string& boxes, const std::string& truth) {
  return error_of([&] { parse_truth_pairs(boxes, "b.json", truth, "t.json"); });
}
}  // namespace

TEST(ToiTruth, CollidingPairsInFileOrder) {
  const auto t = parse_truth_pairs("[[0, 17], [3, 20],\r\n [4294967295, 0]]", "b.json", "[true, false, true]", "t.json");
  EXPECT_EQ(t.listed, 3u);
  ASSERT_EQ(t.colliding.size(), 2u);
  EXPECT_EQ(t.colliding[0], (std::array<std::uint32_t, 2>{0, 17}));
  EXPECT_EQ(t.colliding[1], (std::array<std::uint32_t, 2>{4294967295u, 0}));
  EXPECT_EQ(parse_truth_pairs("[]", "b", "[]", "t").listed, 0u);
}

TEST(ToiTruth, RefusalsNameTheFileAndEntry) {
  EXPECT_EQ(error_for("[[0, 1]]", "[true, false]"), "t.json: 2 booleans for 1 pairs in b.json");
  EXPECT_EQ(error_for("{}", "[]"), "b.json: expected a JSON array of [id, id] pairs");
  EXPECT_EQ(error_for("[]", "true"), "t.json: expected a JSON array of booleans");
  for (const char* pair : {"[0]", "[0, 1, 2]", "[-1, 2]", "[1.5, 2]", "[\"1\", 2]", "[4294967296, 0]", "7", "{}",
                           "[0, [1]]", "[[0, 1]]", "[0, {\"a\": 1}]", "null", "[]"})
    EXPECT_EQ(error_for(std::string("[[0, 1], ") + pair + "]", "[true, true]"),
              "b.json: pair 1: expected [id, id] with ids in [0, 2^32)")
        << pair;
  EXPECT_EQ(error_for("[[0, 1]]", "[1]"), "t.json: entry 0: expected a boolean");
  for (const char* entry : {"[true]", "{}", "null", "\"true\""})
    EXPECT_EQ(error_for("[[0, 1], [2, 3]]", std::string("[false, ") + entry + "]"), "t.json: entry 1: expected a boolean")
        << entry;
  EXPECT_EQ(error_for("[]", "{\"a\": [true]}"), "t.json: expected a JSON array of booleans");
  // The first malformed entry in file order, the boxes' first at the same index.
  EXPECT_EQ(error_for("[[0, 1], [2], [4, 5]]", "[true, true, 3]"), "b.json: pair 1: expected [id, id] with ids in [0, 2^32)");
  EXPECT_EQ(error_for("[[0, 1], [2, 3], [4]]", "[true, 0, true]"), "t.json: entry 1: expected a boolean");
  EXPECT_EQ(error_for("[[0, 1], [2]]", "[true, 0]"), "b.json: pair 1: expected [id, id] with ids in [0, 2^32)");
  EXPECT_NE(error_for("[[0, 1]", "[true]").find("b.json: invalid JSON: "), std::string::npos);
  EXPECT_NE(error_for("[[0, 1]]", "[tru]").find("t.json: invalid JSON: "), std::string::npos);
  EXPECT_NE(error_of([] { mccd::cli::read_truth_pairs("/nonexistent/b.json", "/nonexistent/t.json"); })
                .find("/nonexistent/b.json: cannot open"),
            std::string::npos);
}
