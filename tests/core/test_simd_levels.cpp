// Every instruction set of the lane kernels (geometry/lane_masks.h) this processor has gives
// the same steps: the same contacts and the same counts, on every generated scene at every step
// and on the real cloth-ball step, with fbd and with brute force as the reference.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <mccd/parallel/scene.h>
#include <mccd/geometry/frame_sequence.h>
#include <mccd/geometry/lane_masks.h>

#include "fixtures/scenes.h"
#include "support/data.h"
#include "support/real_step.h"
#include "support/simd_levels.h"

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) { return {frame.begin(), frame.end()}; }

std::vector<detail::SimdLevel> levels() {
  std::vector<detail::SimdLevel> out;
  using L = detail::SimdLevel;
  for (L l : {L::Scalar, L::Sse2, L::Avx2, L::Avx512})
    if (detail::lane_kernels_for(l)) out.push_back(l);
  return out;
}

struct Steps {
  std::vector<StepResult> steps;
};

Steps run(const AnimatedScene& s, detail::SimdLevel level, const SceneOptions& options = {}) {
  detail::select_simd_level(level);
  Scene scene(s.meshes, options);
  Steps r;
  for (std::size_t f = 1; f < s.frames.size(); ++f) r.steps.push_back(scene.advance(views(s.frames[f])));
  return r;
}

void expect_same(const Steps& a, const Steps& b, const std::string& what) {
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (std::size_t i = 0; i < a.steps.size(); ++i) {
    const StepStats &x = a.steps[i].stats, &y = b.steps[i].stats;
    ASSERT_EQ(a.steps[i].contacts, b.steps[i].contacts) << what << " step " << i;
    EXPECT_EQ(x.leaf_pairs, y.leaf_pairs) << what << " step " << i;
    EXPECT_EQ(x.feature_box_tests, y.feature_box_tests) << what << " step " << i;
    EXPECT_EQ(x.vf_filtered, y.vf_filtered) << what << " step " << i;
    EXPECT_EQ(x.ee_filtered, y.ee_filtered) << what << " step " << i;
    EXPECT_EQ(x.vf_tests, y.vf_tests) << what << " step " << i;
    EXPECT_EQ(x.ee_tests, y.ee_tests) << what << " step " << i;
    // the elementary tests' paths: the fast path in lanes decides what the scalar one does
    for (const auto& [cx, cy] : {std::pair{&x.vf_ccd, &y.vf_ccd}, std::pair{&x.ee_ccd, &y.ee_ccd}}) {
      EXPECT_EQ(cx->queries, cy->queries) << what << " step " << i;
      EXPECT_EQ(cx->root_tests, cy->root_tests) << what << " step " << i;
      EXPECT_EQ(cx->fast_hits, cy->fast_hits) << what << " step " << i;
      EXPECT_EQ(cx->fast_misses, cy->fast_misses) << what << " step " << i;
      EXPECT_EQ(cx->hits, cy->hits) << what << " step " << i;
      EXPECT_EQ(cx->pieces, cy->pieces) << what << " step " << i;
    }
  }
}

void check(const AnimatedScene& s) {
  const test::KeepSimdLevel keep;
  SceneOptions brute;
  brute.method = Method::BruteForce;
  const Steps reference = run(s, detail::SimdLevel::Scalar, brute);
  const Steps scalar = run(s, detail::SimdLevel::Scalar);
  for (std::size_t i = 0; i < scalar.steps.size(); ++i)
    ASSERT_EQ(scalar.steps[i].contacts, reference.steps[i].contacts) << s.name << " step " << i << " brute force";
  for (detail::SimdLevel l : levels()) expect_same(run(s, l), scalar, s.name + " " + detail::to_string(l));
}

}  // namespace

TEST(SimdLevels, FoldingCloth) { check(make_folding_cloth(40, 31)); }
TEST(SimdLevels, DeformingSpheres) { check(make_deforming_spheres(4, 10, 31)); }
TEST(SimdLevels, RandomTriangles) { check(make_random_triangles(2000, 21, 3)); }
TEST(SimdLevels, TwistingTube) { check(make_twisting_tube(40, 20, 31)); }

TEST(SimdLevels, ClothBallRealStep) {
  const auto dir = test::cloth_ball_frames();
  MCCD_REQUIRE_DATA(dir);
  const AnimatedScene s = test::cloth_ball_step(dir);
  const test::KeepSimdLevel keep;
  const Steps scalar = run(s, detail::SimdLevel::Scalar);
  for (detail::SimdLevel l : levels())
    if (l != detail::SimdLevel::Scalar)
      expect_same(run(s, l), scalar, std::string("cloth-ball ") + detail::to_string(l));
}
