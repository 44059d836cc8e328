// SceneOptions: every value validate() refuses, refused by the Scene constructor too, and an
// out-of-range method argument refused by step() and advance() before any state changes.
#include <mccd/core/options.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fixtures/scenes.h"
#include "support/errors.h"
#include <mccd/parallel/scene.h>
#include <mccd/geometry/error.h>

using namespace mccd;
using mccd::test::error_of;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

bool mentions(const std::string& message, const std::string& what) {
  return message.find(what) != std::string::npos;
}

}  // namespace

TEST(SceneOptions, DefaultsAreValid) {
  EXPECT_NO_THROW(validate(SceneOptions{}));
  SceneOptions o;
  o.method = Method::BruteForce;
  o.volume = VolumeKind::Aabb;
  o.min_distance = 0.25;
  o.rebuild_sprout_ratio = 1e-9;
  o.rebuild_invalid_ratio = 1e9;
  EXPECT_NO_THROW(validate(o));
}

TEST(SceneOptions, OutOfRangeMethodAndVolumeAreRefused) {
  for (unsigned raw : {4u, 5u, 200u, 255u}) {
    SceneOptions o;
    o.method = static_cast<Method>(raw);
    const std::string m = error_of([&] { validate(o); });
    EXPECT_TRUE(mentions(m, "method " + std::to_string(raw) + " is not a Method")) << m;
    EXPECT_TRUE(mentions(error_of([&] { Scene({make_grid_mesh(2)}, o); }), "is not a Method"));
    SceneOptions v;
    v.volume = static_cast<VolumeKind>(raw - 2);  // 2 is the first value past Aabb
    const std::string mv = error_of([&] { validate(v); });
    EXPECT_TRUE(mentions(mv, "volume " + std::to_string(raw - 2) + " is not a VolumeKind")) << mv;
    EXPECT_TRUE(mentions(error_of([&] { Scene({make_grid_mesh(2)}, v); }), "is not a VolumeKind"));
    SceneOptions r;
    r.representatives = static_cast<Representatives>(raw - 1);  // 3 is the first value past Canonical
    const std::string mr = error_of([&] { validate(r); });
    EXPECT_TRUE(mentions(mr, "representatives " + std::to_string(raw - 1) + " is not a Representatives")) << mr;
    EXPECT_TRUE(mentions(error_of([&] { Scene({make_grid_mesh(2)}, r); }), "is not a Representatives"));
  }
}

TEST(SceneOptions, BadDistancesAndRatiosAreRefused) {
  for (double d : {-1.0, -0.0 - 1e-300, kNaN, kInf, -kInf}) {
    SceneOptions o;
    o.min_distance = d;
    EXPECT_TRUE(mentions(error_of([&] { validate(o); }), "min_distance must be finite and >= 0")) << d;
    EXPECT_TRUE(mentions(error_of([&] { Scene({make_grid_mesh(2)}, o); }), "min_distance")) << d;
  }
  for (double r : {0.0, -0.5, kNaN, -kInf}) {
    SceneOptions a, b;
    a.rebuild_sprout_ratio = r;
    b.rebuild_invalid_ratio = r;
    EXPECT_TRUE(mentions(error_of([&] { validate(a); }), "rebuild ratios must be > 0")) << r;
    EXPECT_TRUE(mentions(error_of([&] { validate(b); }), "rebuild ratios must be > 0")) << r;
    EXPECT_THROW(Scene({make_grid_mesh(2)}, a), Error);
    EXPECT_THROW(Scene({make_grid_mesh(2)}, b), Error);
  }
  SceneOptions zero;
  zero.min_distance = -0.0;  // negative zero is zero
  EXPECT_NO_THROW(validate(zero));
}

TEST(SceneOptions, NamesRoundTripAndUnknownNamesAreRefused) {
  for (Method m : {Method::BruteForce, Method::Traverse, Method::Phc, Method::Fbd})
    EXPECT_EQ(parse_method(to_string(m)), m);
  EXPECT_EQ(parse_method("front"), Method::Fbd);
  for (VolumeKind v : {VolumeKind::Kdop18, VolumeKind::Aabb}) EXPECT_EQ(parse_volume(to_string(v)), v);
  for (Representatives r : {Representatives::Default, Representatives::Leaf, Representatives::Canonical})
    EXPECT_EQ(parse_representatives(to_string(r)), r);
  EXPECT_EQ(error_of([] { parse_representatives("paper"); }),
            "unknown representative rule 'paper' (expected default, leaf or canonical)");
  EXPECT_EQ(error_of([] { parse_method("Front"); }),
            "unknown method 'Front' (expected bruteforce, traverse, phc or fbd)");
  EXPECT_EQ(error_of([] { parse_volume(""); }), "unknown bounding volume '' (expected kdop18 or aabb)");
  EXPECT_STREQ(to_string(static_cast<Method>(9)), "?");
  EXPECT_STREQ(to_string(static_cast<VolumeKind>(9)), "?");
  EXPECT_STREQ(to_string(static_cast<Representatives>(9)), "?");
}

TEST(SceneOptions, DefaultRepresentativesFollowTheTree) {
  SceneOptions o;
  EXPECT_EQ(resolved_representatives(o), Representatives::Leaf);
  o.bvh = BvhBuild::Median;
  EXPECT_EQ(resolved_representatives(o), Representatives::Canonical);
  o.representatives = Representatives::Leaf;
  EXPECT_EQ(resolved_representatives(o), Representatives::Leaf);
  o.bvh = BvhBuild::Sah;
  o.representatives = Representatives::Canonical;
  EXPECT_EQ(resolved_representatives(o), Representatives::Canonical);
}

TEST(SceneOptions, StepRefusesOutOfRangeMethodAndStaysUnchanged) {
  AnimatedScene s = make_folding_cloth(8, 4);
  Scene a(s.meshes), b(s.meshes);
  const std::vector<PositionsView> f1(s.frames[1].begin(), s.frames[1].end());
  const std::vector<PositionsView> f2(s.frames[2].begin(), s.frames[2].end());
  const std::vector<PositionsView> f3(s.frames[3].begin(), s.frames[3].end());
  a.advance(f1);
  b.advance(f1);
  for (unsigned raw : {4u, 255u}) {
    const Method bad = static_cast<Method>(raw);
    EXPECT_EQ(error_of([&] { a.advance(f2, bad); }),
              "Scene: method " + std::to_string(raw) + " is not a Method (expected bruteforce, traverse, phc or fbd)");
    EXPECT_TRUE(mentions(error_of([&] { a.step(f1, f2, bad); }), "is not a Method"));
  }
  // the refused calls changed nothing: the next steps match a scene that never saw them
  for (const auto* next : {&f2, &f3}) {
    const StepResult ra = a.advance(*next), rb = b.advance(*next);
    EXPECT_EQ(ra.contacts, rb.contacts);
    EXPECT_EQ(ra.stats.volume_tests, rb.stats.volume_tests);
    EXPECT_EQ(ra.stats.front_size, rb.stats.front_size);
    EXPECT_EQ(ra.stats.rebuilds, rb.stats.rebuilds);
  }
}
