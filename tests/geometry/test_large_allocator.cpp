// The large-array allocator's huge-page rule and the reserve for caller vectors: sizes on both
// sides of each threshold keep their contents, and the advised part never reaches beyond the
// allocation's whole huge pages.
#include <mccd/geometry/large_allocator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

using namespace mccd::detail;

TEST(LargeAllocator, HugePartAdvisesTheLastPageOnlyWhenThreeQuartersUsed) {
  constexpr std::size_t kFull = kHugePage / 4 * 3;
  EXPECT_EQ(huge_part(0), 0u);
  EXPECT_EQ(huge_part(kHugePage / 2), 0u);
  EXPECT_EQ(huge_part(kFull - 1), 0u);
  EXPECT_EQ(huge_part(kFull), kHugePage);
  EXPECT_EQ(huge_part(kHugePage), kHugePage);
  EXPECT_EQ(huge_part(kHugePage + kFull - 1), kHugePage);
  EXPECT_EQ(huge_part(kHugePage + kFull), 2 * kHugePage);
  for (std::size_t bytes = 1; bytes < 5 * kHugePage; bytes += 4099) {
    const std::size_t part = huge_part(bytes);
    ASSERT_EQ(part % kHugePage, 0u) << bytes;
    // Every whole huge page of the array, and never more than a quarter of a huge page of
    // nothing.
    ASSERT_GE(part, bytes / kHugePage * kHugePage) << bytes;
    if (part > bytes) {
      ASSERT_LE(part - bytes, kHugePage / 4) << bytes;
    }
  }
}

TEST(LargeAllocator, VectorsAcrossTheThresholdsKeepTheirContents) {
  for (std::size_t n : {std::size_t(10), kHugeMin / 8 - 1, kHugeMin / 8, kHugePage / 8 + 7, 3 * kHugePage / 8 + 1}) {
    LargeVector<std::uint64_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = i * 2654435761u;
    v.resize(n + n / 2 + 1);  // moves to a new allocation
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(v[i], i * 2654435761u) << n;
    if (n * 8 >= kHugeMin) {
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % kHugePage, 0u) << n;
    }
  }
}

TEST(LargeAllocator, ReserveHugeGrowsTheCapacityPastTheLastPage) {
  std::vector<double> small;
  reserve_huge(small, 100);
  EXPECT_GE(small.capacity(), 100u);
  for (std::size_t n : {kHugeMin / 8, kHugePage / 8 * 3 + 5}) {
    std::vector<double> v;
    reserve_huge(v, n);
    EXPECT_GE(v.capacity(), n + kHugePage / sizeof(double)) << n;
    v.resize(n, 1.5);
    for (double x : v) ASSERT_EQ(x, 1.5);
  }
  std::vector<int> used{1, 2, 3};  // not empty: a plain reserve
  reserve_huge(used, kHugePage);
  EXPECT_GE(used.capacity(), kHugePage);
  EXPECT_EQ(used, (std::vector<int>{1, 2, 3}));
}

TEST(LargeAllocator, PopulatingPagesKeepsWhatTheyHold) {
  // Backing pages ahead of their first write must not change memory already written: ranges
  // starting and ending inside pages, within one page, empty, and the whole array; then the
  // first touch of a large vector (which populates each chunk) zeroes exactly its elements.
  std::vector<std::uint32_t> v(3 * 4096 + 17);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<std::uint32_t>(i * 2654435761u);
  auto* bytes = reinterpret_cast<unsigned char*>(v.data());
  const std::size_t n = v.size() * sizeof(std::uint32_t);
  for (const auto& [b, e] : std::vector<std::pair<std::size_t, std::size_t>>{
           {0, n}, {1, n - 1}, {4095, 4097}, {100, 100}, {5000, 5001}, {n / 2, n}})
    populate_pages(bytes + b, e - b);
  for (std::size_t i = 0; i < v.size(); ++i) ASSERT_EQ(v[i], static_cast<std::uint32_t>(i * 2654435761u)) << i;

  LargeVector<std::uint64_t> large(kHugePage / 8 * 3 + 5);
  first_touch(large, [](std::size_t count, const auto& body) {
    for (std::size_t b = 0; b < count; b += 1000) body(b, std::min(count, b + 1000));
  });
  for (std::uint64_t x : large) ASSERT_EQ(x, 0u);
}
