// How `mccd run` sums a step's sub-steps into its row (tools/run_table.h): each pair in contact
// during the step counted once however many sub-steps report it, vertex-face and edge-edge
// apart, for any number of sub-steps, checked against a set of the pairs built one by one.
#include "run_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>
#include <vector>

using mccd::Contact;
using mccd::ContactKind;
using mccd::StepResult;
using mccd::cli::StepAccumulator;

namespace {

/// A sub-step's result: `n` random pairs from a small id range (so that sub-steps share many),
/// sorted in the canonical order, each once.
StepResult random_substep(std::mt19937& rng, std::size_t n, std::uint32_t ids) {
  std::uniform_int_distribution<std::uint32_t> id(0, ids - 1), mesh(0, 2), kind(0, 1);
  std::vector<Contact> cs;
  for (std::size_t i = 0; i < n; ++i) {
    Contact c{};
    c.kind = kind(rng) ? ContactKind::EdgeEdge : ContactKind::VertexFace;
    c.mesh_a = mesh(rng);
    c.a = id(rng);
    c.mesh_b = mesh(rng);
    c.b = id(rng);
    c.toi = 0.5;
    cs.push_back(c);
  }
  std::sort(cs.begin(), cs.end());
  cs.erase(std::unique(cs.begin(), cs.end(), [](const Contact& x, const Contact& y) { return !(x < y || y < x); }),
           cs.end());
  StepResult r;
  r.contacts = cs;
  r.earliest_toi = cs.empty() ? INFINITY : 0.5;
  return r;
}

using Pair = std::tuple<int, std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>;

}  // namespace

TEST(StepAccumulator, CountsEachPairOnceOverAnyNumberOfSubsteps) {
  std::mt19937 rng(7);
  for (int substeps : {1, 2, 3, 5, 8, 10, 17}) {
    StepAccumulator acc(substeps);
    for (std::size_t step = 0; step < 3; ++step) {  // the accumulator starts over at each step
      std::set<Pair> vf, ee;
      for (int j = 0; j < substeps; ++j) {
        // some sub-steps empty, some large; ids from a small range so that pairs repeat
        const std::size_t n = (j + step) % 4 == 1 ? 0 : 50 + 300 * std::size_t(j % 3);
        const StepResult r = random_substep(rng, n, 40);
        for (const Contact& c : r.contacts)
          (c.kind == ContactKind::VertexFace ? vf : ee).insert({int(c.kind), c.mesh_a, c.a, c.mesh_b, c.b});
        if (substeps == 1) {  // one sub-step: the step's own counts are taken as they are
          StepResult counted = r;
          counted.stats.vf_contacts = vf.size();
          counted.stats.ee_contacts = ee.size();
          ASSERT_TRUE(acc.add(step, std::size_t(j), counted));
        } else {
          ASSERT_EQ(acc.add(step, std::size_t(j), r), j + 1 == substeps) << "sub-step " << j;
        }
      }
      EXPECT_EQ(acc.row().step, step);
      EXPECT_EQ(acc.row().vf, vf.size()) << substeps << " sub-steps, step " << step;
      EXPECT_EQ(acc.row().ee, ee.size()) << substeps << " sub-steps, step " << step;
    }
  }
}

TEST(StepAccumulator, TheSamePairsInEverySubstepCountOnce) {
  std::mt19937 rng(11);
  const StepResult r = random_substep(rng, 500, 1000);
  std::size_t vf = 0;
  for (const Contact& c : r.contacts) vf += c.kind == ContactKind::VertexFace;
  StepAccumulator acc(6);
  for (std::size_t j = 0; j < 6; ++j) acc.add(4, j, r);
  EXPECT_EQ(acc.row().vf, vf);
  EXPECT_EQ(acc.row().ee, r.contacts.size() - vf);
  EXPECT_EQ(acc.row().first, 4 + 0.5 / 6);  // the first sub-step's impact, in frame time
}
