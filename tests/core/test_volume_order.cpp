// Every order of a feature pair's quarter-volume test and the coplanarity filter
// (SceneOptions::volume_order) gives the same steps: the same contacts as brute force, the same
// feature-pair volume tests and elementary tests, the same query answers; only the count of
// filtered pairs may grow after the filter (it then also counts pairs whose volumes would not
// have met). Checked on every generated scene at every step, and on the real cloth-ball step
// whole and in ten sub-steps (where the adaptive order tests volumes after the filter).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/error.h>

#include "fixtures/scenes.h"
#include "support/data.h"
#include "support/real_step.h"

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) { return {frame.begin(), frame.end()}; }

std::vector<StepResult> run(const AnimatedScene& s, const SceneOptions& options) {
  Scene scene(s.meshes, options);
  std::vector<StepResult> steps;
  for (std::size_t f = 1; f < s.frames.size(); ++f) steps.push_back(scene.advance(views(s.frames[f])));
  return steps;
}

SceneOptions with_order(VolumeOrder order) {
  SceneOptions o;
  o.volume_order = order;
  return o;
}

/// `b` took the same step as `a`, the volumes tested after the filter for some of its pairs:
/// returns b's filtered pairs beyond a's.
std::uint64_t expect_same_step(const StepResult& a, const StepResult& b, const std::string& what) {
  const StepStats &x = a.stats, &y = b.stats;
  EXPECT_EQ(a.contacts, b.contacts) << what;
  EXPECT_EQ(a.earliest_toi, b.earliest_toi) << what;
  EXPECT_EQ(x.leaf_pairs, y.leaf_pairs) << what;
  EXPECT_EQ(x.feature_box_tests, y.feature_box_tests) << what;
  EXPECT_EQ(x.vf_tests, y.vf_tests) << what;
  EXPECT_EQ(x.ee_tests, y.ee_tests) << what;
  EXPECT_GE(y.vf_filtered, x.vf_filtered) << what;
  EXPECT_GE(y.ee_filtered, x.ee_filtered) << what;
  return y.vf_filtered + y.ee_filtered - x.vf_filtered - x.ee_filtered;
}

/// Brute force, then each order; returns the filtered pairs that always testing after the
/// filter adds over always testing first (0: the orders could not be told apart).
std::uint64_t check(const AnimatedScene& s) {
  SceneOptions brute;
  brute.method = Method::BruteForce;
  const std::vector<StepResult> reference = run(s, brute);
  const std::vector<StepResult> first = run(s, with_order(VolumeOrder::First));
  const std::vector<StepResult> after = run(s, with_order(VolumeOrder::AfterFilter));
  const std::vector<StepResult> adaptive = run(s, with_order(VolumeOrder::Adaptive));
  std::uint64_t extra = 0;
  for (std::size_t i = 0; i < first.size(); ++i) {
    const std::string step = s.name + " step " + std::to_string(i);
    EXPECT_EQ(first[i].contacts, reference[i].contacts) << step << " brute force";
    extra += expect_same_step(first[i], after[i], step + " after-filter");
    expect_same_step(first[i], adaptive[i], step + " adaptive");
    EXPECT_LE(adaptive[i].stats.vf_filtered + adaptive[i].stats.ee_filtered,
              after[i].stats.vf_filtered + after[i].stats.ee_filtered)
        << step;
  }
  return extra;
}

/// The simulator queries of every step answer the same in every order.
void check_queries(const AnimatedScene& s) {
  Scene first(s.meshes, with_order(VolumeOrder::First)), after(s.meshes, with_order(VolumeOrder::AfterFilter));
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const auto a = views(s.frames[f - 1]), b = views(s.frames[f]);
    const std::string step = s.name + " step " + std::to_string(f);
    EXPECT_EQ(first.earliest_impact(a, b), after.earliest_impact(a, b)) << step;
    EXPECT_EQ(first.is_collision_free(a, b), after.is_collision_free(a, b)) << step;
    // candidates carry the start of their first quarter: the same quarters reach the narrow phase
    EXPECT_EQ(first.candidates(a, b), after.candidates(a, b)) << step;
  }
}

/// The cloth-ball step in `k` sub-steps (positions moving linearly between its two frames).
AnimatedScene sub_steps(const AnimatedScene& whole, int k) {
  AnimatedScene s;
  s.name = whole.name + " in " + std::to_string(k) + " sub-steps";
  s.meshes = whole.meshes;
  const Positions &x0 = whole.frames[0][0], &x1 = whole.frames[1][0];
  for (int i = 0; i <= k; ++i) {
    const double t = double(i) / k;
    Positions x(x0.rows());
    for (std::size_t j = 0; j < x.xyz().size(); ++j) x.xyz()[j] = i == k ? x1.xyz()[j] : (1 - t) * x0.xyz()[j] + t * x1.xyz()[j];
    s.frames.push_back({x});
  }
  return s;
}

}  // namespace

TEST(VolumeOrder, FoldingCloth) { EXPECT_GT(check(make_folding_cloth(40, 31)), 0u); }
TEST(VolumeOrder, DeformingSpheres) { check(make_deforming_spheres(4, 10, 31)); }
TEST(VolumeOrder, RandomTriangles) { EXPECT_GT(check(make_random_triangles(2000, 21, 3)), 0u); }
TEST(VolumeOrder, TwistingTube) { check(make_twisting_tube(40, 20, 31)); }

TEST(VolumeOrder, QueriesFoldingCloth) { check_queries(make_folding_cloth(30, 16)); }
TEST(VolumeOrder, QueriesRandomTriangles) { check_queries(make_random_triangles(1500, 16, 5)); }

TEST(VolumeOrder, MinimumDistanceTestsFirst) {
  // Without the vector filter in front of the narrow phase there is nothing to save: every
  // order tests the volumes first, counts included.
  const AnimatedScene s = make_folding_cloth(30, 11);
  SceneOptions first = with_order(VolumeOrder::First), after = with_order(VolumeOrder::AfterFilter);
  first.min_distance = after.min_distance = 1e-3;
  const std::vector<StepResult> a = run(s, first), b = run(s, after);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(expect_same_step(a[i], b[i], "step " + std::to_string(i)), 0u);
    EXPECT_EQ(a[i].stats.vf_filtered, b[i].stats.vf_filtered);
  }
}

TEST(VolumeOrder, ClothBallWholeAndSubSteps) {
  const auto dir = test::cloth_ball_frames();
  MCCD_REQUIRE_DATA(dir);
  const AnimatedScene whole = test::cloth_ball_step(dir);
  for (const AnimatedScene& s : {whole, sub_steps(whole, 10)}) {
    const std::vector<StepResult> first = run(s, with_order(VolumeOrder::First));
    const std::vector<StepResult> adaptive = run(s, with_order(VolumeOrder::Adaptive));
    std::uint64_t extra = 0;
    for (std::size_t i = 0; i < first.size(); ++i)
      extra += expect_same_step(first[i], adaptive[i], s.name + " step " + std::to_string(i));
    // The adaptive order: first on the whole step (large motion), after the filter in the
    // sub-steps (a tenth of it).
    if (s.frames.size() == 2)
      EXPECT_LT(extra, first[0].stats.feature_box_tests / 100) << s.name;
    else
      EXPECT_GT(extra, 0u) << s.name;
  }
}

TEST(VolumeOrder, NamesRoundTrip) {
  for (VolumeOrder o : {VolumeOrder::Adaptive, VolumeOrder::First, VolumeOrder::AfterFilter})
    EXPECT_EQ(parse_volume_order(to_string(o)), o);
  EXPECT_THROW(parse_volume_order("later"), Error);
  SceneOptions bad;
  bad.volume_order = static_cast<VolumeOrder>(7);
  EXPECT_THROW(validate(bad), Error);
}
