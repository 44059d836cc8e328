// The front's memory cap (SceneOptions::max_front_bytes): a front over the cap is dropped, not
// kept, so the memory held between steps stays under it, and contacts never change.
#include <gtest/gtest.h>

#include <algorithm>

#include <mccd/core/scene.h>

#include "fixtures/scenes.h"

using namespace mccd;

namespace {

/// Steps `s` with fbd under `cap` beside an uncapped scene; checks contacts step by step and
/// the cap. Returns how many steps kept their front and how many dropped it.
std::pair<int, int> step_capped(const AnimatedScene& s, std::size_t cap, std::uint64_t* largest_uncapped) {
  SceneOptions free_opt, capped_opt;
  capped_opt.max_front_bytes = cap;
  Scene free_scene(s.meshes, free_opt), capped(s.meshes, capped_opt);
  int kept = 0, dropped = 0;
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const std::vector<PositionsView> next(s.frames[f].begin(), s.frames[f].end());
    const StepResult a = free_scene.advance(next), b = capped.advance(next);
    EXPECT_EQ(a.contacts, b.contacts) << s.name << " step " << f;
    EXPECT_EQ(a.earliest_toi, b.earliest_toi) << s.name << " step " << f;
    EXPECT_LE(b.stats.front_bytes, cap) << s.name << " step " << f;
    if (b.stats.front_size == 0) {
      ++dropped;
      EXPECT_EQ(b.stats.front_bytes, 0u);
    } else {
      ++kept;
    }
    if (largest_uncapped) *largest_uncapped = std::max(*largest_uncapped, a.stats.front_bytes);
  }
  return {kept, dropped};
}

}  // namespace

TEST(FrontMemory, TinyCapDropsEveryFrontAndRebuildsEachStep) {
  const AnimatedScene s = make_folding_cloth(30, 21);
  SceneOptions o;
  o.max_front_bytes = 1;
  Scene capped(s.meshes, o);
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const StepResult r = capped.advance(std::vector<PositionsView>(s.frames[f].begin(), s.frames[f].end()));
    EXPECT_EQ(r.stats.front_size, 0u) << "step " << f;
    EXPECT_EQ(r.stats.front_bytes, 0u) << "step " << f;
    EXPECT_EQ(r.stats.rebuilds, 1u) << "step " << f;  // built from the root every step
  }
  const auto [kept, dropped] = step_capped(s, 1, nullptr);
  EXPECT_EQ(kept, 0);
  EXPECT_EQ(dropped, static_cast<int>(s.frames.size()) - 1);
}

TEST(FrontMemory, CapBetweenStepsKeepsSomeFrontsAndDropsOthers) {
  for (const AnimatedScene& s : {make_folding_cloth(30, 21), make_deforming_spheres(3, 16, 11)}) {
    std::uint64_t largest = 0;
    step_capped(s, ~std::size_t(0), &largest);  // uncapped: the largest front it holds
    ASSERT_GT(largest, 0u) << s.name;
    // Under the largest front, so the scene is driven into the cap at least once.
    const auto [kept, dropped] = step_capped(s, static_cast<std::size_t>(largest * 3 / 4), nullptr);
    EXPECT_GT(dropped, 0) << s.name;
  }
}

TEST(FrontMemory, NoCapIsTheDefault) {
  EXPECT_EQ(SceneOptions{}.max_front_bytes, 0u);
  const AnimatedScene s = make_folding_cloth(20, 6);
  Scene sc(s.meshes);
  const StepResult r = sc.advance(std::vector<PositionsView>(s.frames[1].begin(), s.frames[1].end()));
  EXPECT_GT(r.stats.front_size, 0u);
}
