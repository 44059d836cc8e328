// Failure atomicity: a refused step leaves the scene exactly as it was. After any refusal the
// next good steps equal those of a scene that never saw it, contacts and every count of the
// statistics, for every method.
#include <mccd/parallel/scene.h>

#include <gtest/gtest.h>

#include <functional>
#include <utility>
#include <limits>

#include "fixtures/scenes.h"
#include "support/errors.h"
#include <mccd/geometry/error.h>

using namespace mccd;
using mccd::test::error_of;

namespace {

std::vector<PositionsView> views(const std::vector<Positions>& frame) {
  return std::vector<PositionsView>(frame.begin(), frame.end());
}

/// Every count of a step's statistics, by name (times aside).
std::vector<std::pair<std::string, std::uint64_t>> counts(const StepStats& s) {
  std::vector<std::pair<std::string, std::uint64_t>> out{
      {"method", static_cast<std::uint64_t>(s.method)}, {"volume_tests", s.volume_tests},
      {"feature_box_tests", s.feature_box_tests},       {"vf_tests", s.vf_tests},
      {"ee_tests", s.ee_tests},                         {"vf_contacts", s.vf_contacts},
      {"ee_contacts", s.ee_contacts},                   {"leaf_pairs", s.leaf_pairs},
      {"adjacent_leaf_pairs", s.adjacent_leaf_pairs},   {"repeated_leaf_pairs", s.repeated_leaf_pairs},
      {"culled_patches", s.culled_patches},             {"culled_nodes", s.culled_nodes},
      {"sprouted", s.sprouted},                         {"invalidated", s.invalidated},
      {"rebuilds", s.rebuilds},
      {"orphan_vf_tested", s.orphan_vf_tested},         {"orphan_ee_tested", s.orphan_ee_tested},
      {"front_size", s.front_size},                     {"front_bytes", s.front_bytes}};
  for (const auto& [kind, c] : {std::pair{"vf", &s.vf_ccd}, std::pair{"ee", &s.ee_ccd}})
    for (const auto& [name, value] : {std::pair{"queries", c->queries}, std::pair{"box_culled", c->box_culled},
                                      std::pair{"coplanar_culled", c->coplanar_culled},
                                      std::pair{"root_tests", c->root_tests}, std::pair{"fallbacks", c->fallbacks},
                                      std::pair{"hits", c->hits}, std::pair{"touches", c->touches}})
      out.emplace_back(std::string(kind) + "_ccd." + name, value);
  return out;
}

/// Two steps' contacts and every count of their statistics.
void expect_same_step(const StepResult& a, const StepResult& b, const std::string& what) {
  EXPECT_EQ(a.contacts, b.contacts) << what;
  EXPECT_EQ(a.earliest_toi, b.earliest_toi) << what;
  EXPECT_EQ(counts(a.stats), counts(b.stats)) << what;
}

struct Refusal {
  std::string name;
  std::string message;  ///< part of the error message
  std::function<void(Scene&, const AnimatedScene&, std::size_t next_frame)> call;
};

/// Every way a step can be refused, in the middle of a run (frame `f` is the next good one).
std::vector<Refusal> refusals() {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  constexpr double inf = std::numeric_limits<double>::infinity();
  auto with = [](const std::vector<Positions>& frame, std::size_t mesh, std::size_t v, int c, double value) {
    std::vector<Positions> out = frame;
    out[mesh](v, c) = value;
    return out;
  };
  std::vector<Refusal> r;
  r.push_back({"nan in advance", "advance, mesh 1 (sphere1): vertex 5: coordinate y is not finite",
               [=](Scene& s, const AnimatedScene& a, std::size_t f) { s.advance(views(with(a.frames[f], 1, 5, 1, nan))); }});
  r.push_back({"inf in step start", "step start, mesh 0 (sphere0): vertex 0: coordinate x is not finite",
               [=](Scene& s, const AnimatedScene& a, std::size_t f) {
                 s.step(views(with(a.frames[f - 1], 0, 0, 0, inf)), views(a.frames[f]));
               }});
  r.push_back({"-inf in step end", "step end, mesh 1 (sphere1): vertex 7: coordinate z is not finite",
               [=](Scene& s, const AnimatedScene& a, std::size_t f) {
                 s.step(views(a.frames[f - 1]), views(with(a.frames[f], 1, 7, 2, -inf)));
               }});
  r.push_back({"a mesh missing", "advance: 1 position arrays for 2 meshes",
               [](Scene& s, const AnimatedScene& a, std::size_t f) {
                 s.advance(std::vector<PositionsView>{a.frames[f][0]});
               }});
  r.push_back({"too few vertices", "advance, mesh 0 (sphere0): has 3 vertices, expected",
               [](Scene& s, const AnimatedScene& a, std::size_t f) {
                 const Positions few(a.frames[f][0].mat().topRows(3));
                 s.advance(std::vector<PositionsView>{few, a.frames[f][1]});
               }});
  r.push_back({"method out of range", "is not a Method",
               [](Scene& s, const AnimatedScene& a, std::size_t f) { s.advance(views(a.frames[f]), static_cast<Method>(7)); }});
  return r;
}

}  // namespace

TEST(SceneAtomicity, RefusedStepsLeaveNoTraceForEveryMethod) {
  const AnimatedScene a = make_deforming_spheres(2, 8, 7);  // two meshes, genuine contacts
  for (Method m : {Method::BruteForce, Method::Traverse, Method::Phc, Method::Fbd})
    for (const Refusal& refusal : refusals()) {
      const std::string what = std::string(to_string(m)) + ", " + refusal.name;
      SceneOptions o;
      o.method = m;
      Scene tried(a.meshes, o), clean(a.meshes, o);
      std::size_t contacts = 0;
      for (std::size_t f = 1; f < a.frames.size(); ++f) {
        if (f % 2 == 0) {  // refused twice in a row, between good steps
          for (int k = 0; k < 2; ++k) {
            const std::string e = error_of([&] { refusal.call(tried, a, f); });
            EXPECT_NE(e.find(refusal.message), std::string::npos) << what << ": " << e;
          }
        }
        const StepResult rt = tried.advance(views(a.frames[f])), rc = clean.advance(views(a.frames[f]));
        expect_same_step(rt, rc, what + ", frame " + std::to_string(f));
        contacts += rc.contacts.size();
      }
      EXPECT_GT(contacts, 0u) << what;  // the steps compared did find something
    }
}

TEST(SceneAtomicity, RefusedExplicitStepKeepsTheLastEnd) {
  // advance() continues from the last good step's end, not from a refused step's positions
  const AnimatedScene a = make_folding_cloth(10, 5);
  Scene tried(a.meshes), clean(a.meshes);
  tried.advance(views(a.frames[1]));
  clean.advance(views(a.frames[1]));
  std::vector<Positions> bad = a.frames[3];
  bad[0](0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(tried.step(views(a.frames[2]), views(bad)), Error);
  for (std::size_t f = 2; f < a.frames.size(); ++f)
    expect_same_step(tried.advance(views(a.frames[f])), clean.advance(views(a.frames[f])), "frame " + std::to_string(f));
}
