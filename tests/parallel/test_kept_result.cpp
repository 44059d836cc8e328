// Scene::step / Scene::advance into a kept StepResult: the contact list's storage is written
// over from step to step (shorter, longer, or larger than its room), and every step must equal
// the same step returned fresh: contacts, earliest impact and counts. A refused step leaves the
// kept result as it was.
#include <mccd/parallel/scene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

#include "fixtures/scenes.h"
#include <mccd/geometry/error.h>

using namespace mccd;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) {
  return std::vector<PositionsView>(frame.begin(), frame.end());
}

void expect_same(const StepResult& kept, const StepResult& fresh, const std::string& what) {
  EXPECT_EQ(kept.contacts, fresh.contacts) << what;
  EXPECT_EQ(kept.earliest_toi, fresh.earliest_toi) << what;
  EXPECT_EQ(kept.stats.vf_contacts, fresh.stats.vf_contacts) << what;
  EXPECT_EQ(kept.stats.ee_contacts, fresh.stats.ee_contacts) << what;
  EXPECT_EQ(kept.stats.leaf_pairs, fresh.stats.leaf_pairs) << what;
  EXPECT_EQ(kept.stats.volume_tests, fresh.stats.volume_tests) << what;
}

/// Steps `s` in two scenes, one returning fresh results and one into a kept result (by
/// advance, every third step by an explicit step), and compares them. Returns the contact
/// counts of the steps.
std::vector<std::size_t> compare_kept(const AnimatedScene& s, Method m, StepResult& kept) {
  SceneOptions o;
  o.method = m;
  Scene fresh_scene(s.meshes, o), kept_scene(s.meshes, o);
  std::vector<std::size_t> counts;
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const std::string what = s.name + ", " + to_string(m) + ", step " + std::to_string(f);
    StepResult fresh;
    if (f % 3 == 0) {
      fresh = fresh_scene.step(views(s.frames[f - 1]), views(s.frames[f]));
      kept_scene.step(views(s.frames[f - 1]), views(s.frames[f]), kept);
    } else {
      fresh = fresh_scene.advance(views(s.frames[f]));
      kept_scene.advance(views(s.frames[f]), kept);
    }
    expect_same(kept, fresh, what);
    counts.push_back(fresh.contacts.size());
  }
  return counts;
}

}  // namespace

TEST(KeptResult, EqualsFreshResultsAsTheListGrowsAndShrinks) {
  // The folding cloth's contacts grow past the join's parallel threshold (1024) and the random
  // triangles' go up and down: the kept list is shortened, lengthened within its room, and
  // reallocated.
  for (const AnimatedScene& s : {make_folding_cloth(40, 12), make_random_triangles(1500, 10, 3)})
    for (Method m : {Method::Traverse, Method::Phc, Method::Fbd}) {
      StepResult kept;
      const std::vector<std::size_t> counts = compare_kept(s, m, kept);
      bool up = false, down = false;
      for (std::size_t i = 1; i < counts.size(); ++i) {
        up = up || counts[i] > counts[i - 1];
        down = down || counts[i] < counts[i - 1];
      }
      EXPECT_TRUE(up) << s.name;
      EXPECT_TRUE(down) << s.name;
    }
  const std::vector<std::size_t> cloth = [] {
    StepResult kept;
    return compare_kept(make_folding_cloth(40, 12), Method::Fbd, kept);
  }();
  EXPECT_GT(*std::max_element(cloth.begin(), cloth.end()), 1024u) << "the large join is not exercised";
}

TEST(KeptResult, StaleContentsAreWrittenOver) {
  // A kept result holding another scene's list (longer and shorter than the steps') and stale
  // figures: every step replaces all of it.
  const AnimatedScene s = make_deforming_spheres(3, 8, 8);
  for (std::size_t stale : {0u, 3u, 5000u}) {
    StepResult kept;
    Contact junk{};
    junk.kind = ContactKind::EdgeEdge;
    junk.mesh_a = junk.mesh_b = 99;
    junk.a = junk.b = 12345;
    junk.a_vertices = {7, 8};
    junk.toi = 0.5;
    kept.contacts.assign(stale, junk);
    kept.earliest_toi = -1;
    kept.stats.vf_contacts = 777;
    compare_kept(s, Method::Fbd, kept);
  }
}

TEST(KeptResult, RefusedStepLeavesTheKeptResult) {
  const AnimatedScene s = make_deforming_spheres(2, 8, 5);
  Scene scene(s.meshes);
  StepResult kept;
  scene.advance(views(s.frames[1]), kept);
  scene.advance(views(s.frames[2]), kept);
  const StepResult before = kept;
  std::vector<Positions> bad = s.frames[3];
  bad[1](4, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(scene.advance(views(bad), kept), Error);
  EXPECT_THROW(scene.step(views(s.frames[2]), views(bad), kept), Error);
  EXPECT_THROW(scene.advance(views(s.frames[3]), kept, static_cast<Method>(9)), Error);
  EXPECT_EQ(kept.contacts, before.contacts);
  EXPECT_EQ(kept.earliest_toi, before.earliest_toi);
  EXPECT_EQ(kept.stats.leaf_pairs, before.stats.leaf_pairs);
  // and the scene goes on from the last good step
  Scene clean(s.meshes);
  clean.advance(views(s.frames[1]));
  clean.advance(views(s.frames[2]));
  scene.advance(views(s.frames[3]), kept);
  expect_same(kept, clean.advance(views(s.frames[3])), "after the refusals");
}
