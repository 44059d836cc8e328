// The join's order of contacts: the packed bucket sort against a plain sort of the keys.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include <mccd/parallel/contact_buffer.h>

#include "fixtures/shapes.h"

namespace mccd::detail {
namespace {

// Unique random keys with ids below 2^id_bits, in random order.
std::vector<std::uint64_t> random_keys(std::size_t n, unsigned id_bits, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::set<std::uint64_t> seen;
  std::vector<std::uint64_t> keys;
  const std::uint64_t ids = std::uint64_t(1) << id_bits;
  while (keys.size() < n) {
    const auto kind = rng() & 1 ? ContactKind::EdgeEdge : ContactKind::VertexFace;
    const auto a = static_cast<std::uint32_t>(rng() % ids), b = static_cast<std::uint32_t>(rng() % ids);
    const std::uint64_t k = RawContact::make_key(kind, a, b);
    if (seen.insert(k).second) keys.push_back(k);
  }
  return keys;
}

TEST(ContactOrder, PackedOrderIsTheOrderOfTheKeys) {
  for (const auto& [n, id_bits] : std::vector<std::pair<std::size_t, unsigned>>{
           {0, 1}, {1, 1}, {2, 1}, {3, 2}, {1000, 5}, {1025, 6}, {2500, 12}, {5000, 12}, {100000, 18},
           {20000, 24}}) {  // the last: 64 bits exactly
    const std::vector<std::uint64_t> keys = random_keys(n, id_bits, static_cast<std::uint32_t>(n + id_bits));
    LargeVector<std::uint64_t> order;
    ASSERT_TRUE(packed_key_order(keys.begin(), n, id_bits, order))
        << n << " contacts, " << id_bits << " id bits";
    ASSERT_EQ(order.size(), n);
    std::vector<std::uint64_t> sorted = keys;
    std::sort(sorted.begin(), sorted.end());
    const std::uint64_t mask = (std::uint64_t(1) << position_bits(n)) - 1;
    std::vector<bool> used(n, false);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t pos = order[i] & mask;
      ASSERT_LT(pos, n);
      ASSERT_FALSE(used[pos]) << "position " << pos << " twice";
      used[pos] = true;
      ASSERT_EQ(keys[pos], sorted[i]) << "entry " << i << " of " << n << " (" << id_bits << " id bits)";
    }
  }
}

// Keys crowded into one bucket (every id in a narrow range at the top): the large bucket is
// sorted on its own, with the same result.
TEST(ContactOrder, CrowdedKeysKeepTheirOrder) {
  std::mt19937_64 rng(11);
  std::set<std::uint64_t> seen;
  std::vector<std::uint64_t> keys;
  const std::uint32_t base = (1u << 20) - 512;  // a in [2^20 - 512, 2^20): one top bucket
  while (keys.size() < 100000) {
    const auto a = static_cast<std::uint32_t>(base + rng() % 512), b = static_cast<std::uint32_t>(rng() % (1u << 20));
    const std::uint64_t k = RawContact::make_key(ContactKind::EdgeEdge, a, b);
    if (seen.insert(k).second) keys.push_back(k);
  }
  LargeVector<std::uint64_t> order;
  ASSERT_TRUE(packed_key_order(keys.begin(), keys.size(), 20, order));
  std::vector<std::uint64_t> sorted = keys;
  std::sort(sorted.begin(), sorted.end());
  const std::uint64_t mask = (std::uint64_t(1) << position_bits(keys.size())) - 1;
  for (std::size_t i = 0; i < keys.size(); ++i) ASSERT_EQ(keys[order[i] & mask], sorted[i]) << "entry " << i;
}

// The buckets' sorting runs: whole buckets in order, each run the shortest that reaches its
// share (the last one whatever is left), on bucket sizes from empty to many times the share.
TEST(ContactOrder, BucketRunsHoldAboutAShareEach) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t nb = 1 + rng() % 300, share = 1 + rng() % 50;
    std::vector<std::uint32_t> start(nb + 1, 0);
    start[0] = rng() % 3;  // (a bucket list may start anywhere)
    for (std::size_t b = 0; b < nb; ++b) {
      const unsigned pick = rng() % 10;
      start[b + 1] = start[b] + (pick < 4 ? 0 : pick < 9 ? rng() % 8 : rng() % (5 * share));
    }
    const std::vector<std::uint32_t> runs = bucket_runs(start.data(), nb, share);
    ASSERT_GE(runs.size(), 2u);
    ASSERT_EQ(runs.front(), 0u);
    ASSERT_EQ(runs.back(), nb);
    for (std::size_t r = 0; r + 1 < runs.size(); ++r) {
      ASSERT_LT(runs[r], runs[r + 1]) << "trial " << trial << ", run " << r;
      const std::uint32_t held = start[runs[r + 1]] - start[runs[r]];
      const std::uint32_t before_last = start[runs[r + 1] - 1] - start[runs[r]];
      if (r + 2 < runs.size()) {
        EXPECT_GE(held, share) << "trial " << trial << ", run " << r;
      }
      EXPECT_LT(before_last, share) << "trial " << trial << ", run " << r;
    }
  }
}

TEST(ContactOrder, RefusesWhenKeyAndPositionDoNotFitOneWord) {
  // 1 + 2 * 31 key bits and 2 position bits: 65.
  const std::vector<std::uint64_t> keys = random_keys(3, 31, 7);
  LargeVector<std::uint64_t> order{1, 2};
  EXPECT_FALSE(packed_key_order(keys.begin(), keys.size(), 31, order));
  EXPECT_TRUE(order.empty());
  EXPECT_EQ(position_bits(3), 2u);
  EXPECT_EQ(position_bits(2), 1u);
  EXPECT_EQ(position_bits(1), 1u);
  EXPECT_EQ(position_bits(1u << 20), 20u);
  EXPECT_EQ(position_bits((1u << 20) + 1), 21u);
}

// The join gives the same contacts, in the canonical order, through the packed order and
// through the record sort, over two meshes (mesh-local ids) and on both sides of the size
// where the join goes parallel.
TEST(ContactOrder, JoinIsTheSameThroughBothSorts) {
  const std::vector<TriMesh> meshes{make_grid_mesh(40), make_sphere_mesh(20, 30)};
  SceneTopology scene(scene_faces(meshes), {});
  const MeshTopology& topo = scene.topology();
  for (std::size_t n : {std::size_t(0), std::size_t(100), kParallelJoin, kParallelJoin + 1, std::size_t(3000),
                        std::size_t(30000)}) {
    std::mt19937 rng(static_cast<std::uint32_t>(n));
    std::set<std::uint64_t> seen;
    ContactBuffer buffer;
    while (buffer.size() < n) {
      RawContact c{};
      if (rng() % 3 == 0) {
        const auto v = static_cast<std::uint32_t>(rng() % topo.num_vertices());
        const auto f = static_cast<std::uint32_t>(rng() % topo.num_faces());
        c.key = RawContact::make_key(ContactKind::VertexFace, v, f);
        const Triangle& t = topo.faces()[f];
        c.vertices[0] = v, c.vertices[1] = t[0], c.vertices[2] = t[1], c.vertices[3] = t[2];
      } else {
        auto a = static_cast<std::uint32_t>(rng() % topo.num_edges());
        auto b = static_cast<std::uint32_t>(rng() % topo.num_edges());
        if (a == b) continue;
        if (a > b) std::swap(a, b);
        c.key = RawContact::make_key(ContactKind::EdgeEdge, a, b);
        const Edge& ea = topo.edges()[a];
        const Edge& eb = topo.edges()[b];
        c.vertices[0] = ea[0], c.vertices[1] = ea[1], c.vertices[2] = eb[0], c.vertices[3] = eb[1];
      }
      c.toi = std::uniform_real_distribution<double>(0, 1)(rng);
      if (seen.insert(c.key).second) buffer.push_back(c);
    }
    JoinScratch scratch;
    StepResult packed, records;
    join_contacts(buffer, scratch, scene, packed, true);
    join_contacts(buffer, scratch, scene, records, false);
    ASSERT_EQ(packed.contacts.size(), n);
    EXPECT_TRUE(std::is_sorted(packed.contacts.begin(), packed.contacts.end())) << n;
    EXPECT_TRUE(packed.contacts == records.contacts) << n;
    EXPECT_EQ(packed.stats.vf_contacts, records.stats.vf_contacts);
    EXPECT_EQ(packed.stats.vf_contacts + packed.stats.ee_contacts, n);
    EXPECT_EQ(packed.earliest_toi, records.earliest_toi);
    for (std::size_t i = 1; i < packed.contacts.size(); ++i)
      ASSERT_TRUE(packed.contacts[i - 1] < packed.contacts[i]) << "contacts " << i - 1 << " and " << i;
  }
}


// The narrow phase's queue (core/worker_output.h): entries written past the end through room()
// are kept up to set_end(), in order, and growing keeps every entry kept so far.
TEST(PairQueue, KeepsWhatSetEndKeepsAcrossGrowth) {
  PairQueue q;
  std::vector<std::uint32_t> expect;
  std::uint32_t next = 0;
  for (int round = 0; round < 200; ++round) {
    q.push_back(QueuedPair{{next, 0, 0, 0}, next, 0, 0, 0, 0, 0});
    expect.push_back(next++);
    QueuedPair* end = q.room(64);
    for (int i = 0; i < 64; ++i, ++next) {
      *end = QueuedPair{{next, 0, 0, 0}, next, 0, 0, 0, 0, 0};
      const bool keep = next % 3 == 0;
      if (keep) expect.push_back(next);
      end += keep;
    }
    q.set_end(end);
  }
  ASSERT_EQ(q.size(), expect.size());
  for (std::size_t i = 0; i < expect.size(); ++i) ASSERT_EQ(q.data()[i].a, expect[i]) << "entry " << i;
  q.clear();
  EXPECT_TRUE(q.empty());
}

}  // namespace
}  // namespace mccd::detail
