// MCCD_ASSERT (geometry/assert.h), switched on in this translation unit whatever the build
// type: a failed check prints "internal check failed" with its message and aborts; a passing
// one does nothing and evaluates its condition once. The check on front nodes in
// BvttFront::track / track_readonly (core/front.h) catches a node out of range before it is
// used. Everything instantiated here uses types of this file only (the leaf handler below), so
// no other translation unit's copy of a template, compiled without the checks, stands in.
#ifndef MCCD_ENABLE_ASSERTS
#define MCCD_ENABLE_ASSERTS
#endif

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

#include <mccd/core/bvh.h>
#include <mccd/core/bvtt.h>
#include <mccd/core/front.h>
#include <mccd/core/query.h>
#include <mccd/core/scene_topology.h>
#include <mccd/geometry/assert.h>
#include <mccd/geometry/quarter_volumes.h>

#include "fixtures/shapes.h"

using namespace mccd;
using namespace mccd::detail;

namespace {

/// A leaf handler that counts what it is handed (this file's own type).
struct CountingLeaf {
  mutable std::size_t processed = 0;
  bool skips(std::uint32_t, std::uint32_t) const { return false; }
  void process(std::uint32_t, std::uint32_t, unsigned, WorkerOutput&) const { ++processed; }
  void finish(WorkerOutput&) const {}
  unsigned touch(std::uint32_t, std::uint32_t) const { return 0; }
};

using Volume = QuarterVolume<Kdop18>;

/// A small grid's BVH, every node volume the whole grid (everything overlaps), and its BVTT.
struct Tiny {
  TriMesh mesh = make_grid_mesh(4);
  SceneFaces faces = scene_faces({mesh});
  SceneTopology topo{faces, {}, Representatives::Leaf};
  BvhTopology bvh{triangle_bounds(faces.faces, mesh.vertices), BvhBuild::Sah, 1, faces.face_offsets, &faces.faces};
  LargeVector<Volume> nodes;
  CountingLeaf leaf;
  QueryState query;
  std::unique_ptr<Bvtt<Volume, CountingLeaf>> bvtt;
  Tiny() {
    Kdop18 d = Kdop18::empty();
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) d.add_point(mesh.vertices.point(v));
    Volume all = Volume::empty();
    for (int q = 0; q < 4; ++q) all.set(q, d);
    nodes.assign(bvh.size(), all);
    query.reset(StepKind::Full);
    bvtt = std::make_unique<Bvtt<Volume, CountingLeaf>>(bvh, nodes, topo, leaf, query);
  }
};

void track_one(const Tiny& t, NodePair n) {
  WorkerOutput out;
  BvttFront::track(*t.bvtt, &n, &n + 1, out);
}

void track_readonly_one(const Tiny& t, NodePair n) {
  WorkerOutput out;
  BvttFront::track_readonly(*t.bvtt, &n, &n + 1, out);
}

}  // namespace

TEST(AssertDeathTest, TrackRejectsAFrontNodeOutOfRange) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const Tiny t;
  const auto size = static_cast<std::uint32_t>(t.bvh.size());
  EXPECT_DEATH(track_one(t, NodePair{size + 5, size + 6}), "internal check failed: front node out of range");
  EXPECT_DEATH(track_one(t, NodePair{0, size}), "internal check failed");  // b one past the end
  EXPECT_DEATH(track_one(t, NodePair{2, 1}), "internal check failed");     // a > b
  EXPECT_DEATH(track_readonly_one(t, NodePair{size + 5, size + 6}), "internal check failed: front node out of range");
}

TEST(AssertDeathTest, FailedCheckPrintsConditionAndMessage) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const int x = 3;
  EXPECT_DEATH(MCCD_ASSERT(x == 4, "x is not four"), "internal check failed: x is not four \\(x == 4\\)");
}

TEST(Assert, PassingCheckDoesNothingAndEvaluatesOnce) {
  int evaluated = 0;
  MCCD_ASSERT(true, "never printed");
  MCCD_ASSERT((++evaluated, true), "never printed");
  EXPECT_EQ(evaluated, 1);
  // A valid front node is tracked as usual: the root pair of the grid's two halves overlaps
  // (every volume is the whole grid), so it is expanded down to leaf pairs, all processed.
  const Tiny t;
  const NodePair n{t.bvh.left(0), t.bvh.right(0)};
  WorkerOutput out;
  BvttFront::track(*t.bvtt, &n, &n + 1, out);
  EXPECT_GT(out.front.size(), 1u);
  EXPECT_EQ(t.leaf.processed, out.front.size()) << "every sprouted node is a processed leaf pair";
}
