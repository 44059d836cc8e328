// The exact certificate of touching contacts (geometry/ccd_touch.h), through the whole
// elementary tests: random queries whose points move in one plane, so that a vertex passes
// exactly through an edge of the face, or an edge end exactly through the other edge, each
// checked against the exact GMP reference. A certified touch must be a true contact with a
// time of impact that is not late; the certificate must decide most touching queries (without
// it the search ends in the long-double pass); a point that crosses the edge's line outside the
// edge must never be certified.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <string>

#include <mccd/geometry/ccd.h>
#include <mccd/geometry/ccd_detail.h>
#include <mccd/geometry/ccd_touch.h>
#include <mccd/parallel/scene.h>
#include "fixtures/scenes.h"
#include "support/exact_ccd.h"

using namespace mccd;

namespace {

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(g); }
  double grid(int range, int bits) { return std::ldexp(double(uniform(-range, range)), -bits); }
};

// Points of the plane x + y + z = c (or y = c when `axis_plane`), on dyadic grids coarse
// enough that every sum and product below is exact.
struct Plane {
  bool axis_plane;
  double c;
  Vec3 point(double u, double w) const { return axis_plane ? Vec3(u, c, w) : Vec3(u, w, c - u - w); }
  Vec3 direction(double u, double w) const { return axis_plane ? Vec3(u, 0, w) : Vec3(u, w, -u - w); }
};

// Positions at the contact time tc and velocities: start = x - tc v, end = x + (1 - tc) v.
CcdPoints at_contact(const std::array<Vec3, 4>& x, const std::array<Vec3, 4>& v, double tc, double scale) {
  CcdPoints p;
  for (int i = 0; i < 4; ++i) {
    p.start[i] = (x[i] - tc * v[i]) * scale;
    p.end[i] = (x[i] + (1 - tc) * v[i]) * scale;
  }
  return p;
}

struct Tally {
  int cases = 0, truths = 0, certified = 0, long_pass = 0;
  long pieces = 0;  ///< search pieces over all cases
};

// One query: point `x[i]` at parameter `lambda` of the segment (x[j], x[k]) at time tc, every
// one of those three moving in the plane; the fourth point off the plane (VF: the face's
// third corner) or in it (EE: the other end of the edge), as `fourth_in_plane` says.
void check(bool vf, std::uint64_t seed, bool inside, Tally& t, double offset = 0) {
  Rng r(seed);
  const Plane pl{r.uniform(0, 1) == 0, r.grid(64, 4)};
  const double tc = std::ldexp(double(r.uniform(1, 255)), -8);
  const double lambda = inside ? std::ldexp(double(r.uniform(1, 15)), -4)
                               : (r.uniform(0, 1) ? 1 : -1) * std::ldexp(double(r.uniform(17, 31)), -4) + 0.5;
  const double scale = std::ldexp(1.0, 8 * r.uniform(-4, 4));
  auto in_plane = [&] { return pl.point(r.grid(64, 4), r.grid(64, 4)); };
  auto in_plane_velocity = [&] { return pl.direction(r.grid(64, 4), r.grid(64, 4)); };
  // VF: p = 0, edge (1, 2), corner 3 off the plane. EE: end 2 of edge (2, 3) touches edge (0, 1).
  const int i = vf ? 0 : 2, j = vf ? 1 : 0, k = vf ? 2 : 1, other = 3;
  std::array<Vec3, 4> x, v;
  x[j] = in_plane();
  x[k] = in_plane();
  x[i] = x[j] + lambda * (x[k] - x[j]);
  for (const int m : {i, j, k}) v[m] = in_plane_velocity();
  const bool fourth_in_plane = !vf && r.uniform(0, 1) == 1;
  const Vec3 normal = pl.axis_plane ? Vec3(0, 1, 0) : Vec3(1, 1, 1);
  // Off the plane on one side at both times (the face meets the plane only along its edge).
  x[other] = fourth_in_plane ? in_plane() : in_plane() + normal * std::ldexp(double(r.uniform(2, 64)), -4);
  v[other] = in_plane_velocity();
  x[i] = x[i] + offset * normal;  // off the plane: passes beside the edge
  const CcdPoints p = at_contact(x, v, tc, scale);
  const test::ExactResult ref = vf ? test::exact_vertex_face(p) : test::exact_edge_edge(p);
  CcdCounters counters;
  double toi = -1;
  const bool hit = vf ? vertex_face_ccd(p, toi, {}, &counters) : edge_edge_ccd(p, toi, {}, &counters);
  const std::string what = std::string(vf ? "VF" : "EE") + " seed " + std::to_string(seed) +
                           (inside ? " inside" : " outside") + " offset " + std::to_string(offset) + " tc " +
                           std::to_string(tc);
  ++t.cases;
  t.truths += ref.hit;
  if (ref.hit) {
    EXPECT_TRUE(hit) << what << ": false negative";
    if (hit) {
      EXPECT_TRUE(test::time_not_after(toi, ref.toi)) << what << ": toi " << toi << " is late";
    }
  }
  t.long_pass += counters.fallbacks > 0;
  t.pieces += static_cast<long>(counters.pieces);
  if (counters.touches > 0) {
    ++t.certified;
    EXPECT_TRUE(ref.hit) << what << ": a touch certified where the exact reference finds no contact";
  }
}

// 400 queries with the point crossing inside the segment, 400 outside, each checked.
void run_families(bool vf, Tally& in, Tally& out) {
  for (std::uint64_t s = 0; s < 400; ++s) check(vf, s, true, in);
  for (std::uint64_t s = 1000; s < 1400; ++s) check(vf, s, false, out);
  std::cout << "[ touch " << (vf ? "VF" : "EE") << "] inside: " << in.cases << " cases, " << in.truths
            << " contacts, " << in.certified << " certified, " << in.long_pass << " to the long-double pass, "
            << in.pieces << " search pieces; outside: "
            << out.cases << " cases, " << out.truths << " contacts, " << out.certified << " certified\n";
}

}  // namespace

TEST(CcdTouchCertificate, VertexThroughAnEdgeOfTheFace) {
  Tally in, out;
  run_families(true, in, out);
  // The vertex reaches the edge's interior at tc by construction: a contact, every time.
  EXPECT_EQ(in.truths, in.cases);
  EXPECT_GE(in.certified, in.cases * 9 / 10);
  EXPECT_LE(in.long_pass, in.cases / 50);
  // Outside, the vertex meets the face only if it crosses the edge's line a second time,
  // inside the edge (the face meets the plane only along that edge): mostly misses, and
  // check() failed any certificate the reference does not confirm.
  EXPECT_GE(out.cases - out.truths, out.cases / 2);
}

TEST(CcdTouchCertificate, EdgeEndThroughTheOtherEdge) {
  Tally in, out;
  run_families(false, in, out);
  // Edges in one plane often touch already at t = 0 or stay crossed through t = 1: the exact
  // predicates at the ends decide those first; the certificate most of the others.
  EXPECT_EQ(in.truths, in.cases);
  EXPECT_GE(in.certified, in.cases / 2);
  EXPECT_LE(in.long_pass, in.cases / 50);
  // Outside, the end misses the edge at tc; the edges may still meet at another time (the
  // reference decides, and check() failed any certificate it does not confirm).
  EXPECT_GE(out.cases - out.truths, out.cases / 4);
}

TEST(CcdTouchCertificate, NeverCertifiesAPointBesideTheEdge) {
  // The point moves in a plane 2^-20 or 2^-40 away from the edge's (on either side): it passes
  // beside the edge, through the face or past it, never exactly through the edge. The reference
  // decides, and check() fails any certificate it does not confirm. A vertex-face pair then has
  // nothing to certify; an edge-edge pair may (the other points still share a plane).
  for (const bool vf : {true, false}) {
    Tally t;
    for (const double off : {0x1p-20, -0x1p-20, 0x1p-40, -0x1p-40})
      for (std::uint64_t s = 0; s < 100; ++s) check(vf, s, true, t, off);
    std::cout << "[ beside " << (vf ? "VF" : "EE") << "] " << t.cases << " cases, " << t.truths << " contacts, "
              << t.certified << " certified\n";
    if (vf) {
      EXPECT_EQ(t.certified, 0);
    }
    EXPECT_GT(t.cases - t.truths, 0);
  }
}

namespace {

// A point-segment pair prepared on its own (nothing shared with the query's other pairs).
mccd::detail::touch::PointSegment alone(const mccd::detail::Setup<double>& S, int i, int j, int k) {
  mccd::detail::touch::PointSegment ps;
  mccd::detail::touch::SharedPlane fresh;
  ps.prepare(S, i, j, k, fresh);
  return ps;
}

bool same(const mccd::detail::Bern<2>& a, const mccd::detail::Bern<2>& b) {
  return a.c[0] == b.c[0] && a.c[1] == b.c[1] && a.c[2] == b.c[2];
}

}  // namespace

TEST(CcdTouchCertificate, SharedPlaneDecidesEveryPairAsItsOwnTestsDo) {
  // Queries whose eight points lie in one plane, or all but one (moved off it by 2^-30 at one
  // instant), on grids in tilted planes: the pairs prepared in sequence with the plane the
  // first planar pair found must come out exactly as each pair prepared alone.
  using namespace mccd::detail;
  static constexpr int kVF[3][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}};
  static constexpr int kEE[4][3] = {{0, 2, 3}, {1, 2, 3}, {2, 0, 1}, {3, 0, 1}};
  int planar_pairs = 0, shared_used = 0, off_plane_cases = 0;
  for (std::uint64_t seed = 0; seed < 600; ++seed) {
    Rng r(seed);
    const Plane pl{r.uniform(0, 1) == 0, r.grid(64, 4)};
    mccd::detail::Setup<double> S{};
    for (int m = 0; m < 4; ++m)
      for (V3<double>* at : {&S.s[m], &S.e[m]}) {
        const Vec3 x = pl.point(r.grid(64, 4), r.grid(64, 4));
        *at = {x.x(), x.y(), x.z()};
      }
    if (seed % 3 == 1) {  // one point off the plane at one instant
      V3<double>& x = r.uniform(0, 1) ? S.s[r.uniform(0, 3)] : S.e[r.uniform(0, 3)];
      x.y += 0x1p-30;
      ++off_plane_cases;
    }
    const bool vf = seed % 2 == 0;
    touch::SharedPlane plane;
    for (int c = 0; c < (vf ? 3 : 4); ++c) {
      const int* ijk = vf ? kVF[c] : kEE[c];
      const bool known = plane.state == 2 || plane.state == 1;
      touch::PointSegment ps;
      ps.prepare(S, ijk[0], ijk[1], ijk[2], plane);
      shared_used += known && plane.state == 2;
      const touch::PointSegment ref = alone(S, ijk[0], ijk[1], ijk[2]);
      const std::string what = "seed " + std::to_string(seed) + " pair " + std::to_string(c);
      ASSERT_EQ(ps.planar, ref.planar) << what;
      planar_pairs += ps.planar;
      if (!ps.planar) continue;
      EXPECT_TRUE(same(ps.q, ref.q) && same(ps.r, ref.r) && same(ps.r2, ref.r2)) << what;
      EXPECT_EQ(ps.eq, ref.eq) << what;
    }
  }
  std::cout << "[ shared plane ] " << planar_pairs << " planar pairs, " << shared_used << " decided by the plane, "
            << off_plane_cases << " queries with a point off it\n";
  EXPECT_GT(shared_used, 300);  // the shortcut is taken
  EXPECT_GT(planar_pairs, shared_used);
}

TEST(CcdTouchCertificate, JumpsToATouchInOnePlaneWithoutBisecting) {
  // A vertex (VF) or an edge end (EE) moving in the plane z = 0 crosses a fixed edge's interior
  // at t = 0.3 (not on any dyadic grid), every point in that plane: the cubic clears nothing,
  // so without the window around the crossing the search bisects to pieces of 2^-20. The
  // contact must be found, not late (the exact reference), at most 2^-20 early, in a few pieces.
  for (const bool vf : {true, false}) {
    CcdPoints p;
    if (vf) {  // vertex, then the face (0,0,0), (1,0,0), (0,1,0); it enters through the edge y = 0
      p.start = {Vec3(0.2, -0.3, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
      p.end = {Vec3(0.4, 0.7, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    } else {  // edge (0,0,0)-(1,0,0), and an edge whose first end crosses it
      p.start = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -0.3, 0), Vec3(0.5, -1.3, 0)};
      p.end = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0.7, 0), Vec3(0.5, -0.3, 0)};
    }
    const test::ExactResult ref = vf ? test::exact_vertex_face(p) : test::exact_edge_edge(p);
    ASSERT_TRUE(ref.hit);
    CcdCounters counters;
    double toi = -1;
    const bool hit = vf ? vertex_face_ccd(p, toi, {}, &counters) : edge_edge_ccd(p, toi, {}, &counters);
    const std::string what = vf ? "VF" : "EE";
    ASSERT_TRUE(hit) << what;
    EXPECT_TRUE(test::time_not_after(toi, ref.toi)) << what << ": toi " << toi << " is late";
    EXPECT_GE(toi, 0.3 - 0x1p-20 - 1e-15) << what;
    EXPECT_EQ(counters.touches, 1u) << what;
    EXPECT_LE(counters.pieces, 6u) << what << ": " << counters.pieces << " pieces";
  }
}

namespace {

// The folding cloth (its halves cross along grid lines) stepped through: each contact with its
// four points at the step's start and end goes to `visit(step, contact, points)`. Returns the
// touches the steps certified.
template <class Visit>
std::uint64_t folding_cloth_contacts(const Visit& visit) {
  const AnimatedScene s = make_folding_cloth(16, 9);
  Scene scene(s.meshes);
  std::uint64_t touches = 0;
  for (std::size_t f = 1; f < s.frames.size(); ++f) {
    const Positions &x0 = s.frames[f - 1][0], &x1 = s.frames[f][0];
    const StepResult r = scene.advance(std::vector<PositionsView>(s.frames[f].begin(), s.frames[f].end()));
    touches += r.stats.vf_ccd.touches + r.stats.ee_ccd.touches;
    for (const Contact& c : r.contacts) {
      std::array<std::uint32_t, 4> v{};
      if (c.kind == ContactKind::VertexFace) {
        const Triangle& t = s.meshes[0].faces[c.b];
        v = {c.a, t[0], t[1], t[2]};
      } else {
        v = {c.a_vertices[0], c.a_vertices[1], c.b_vertices[0], c.b_vertices[1]};
      }
      CcdPoints p;
      for (int i = 0; i < 4; ++i) p.start[i] = x0.point(v[i]), p.end[i] = x1.point(v[i]);
      visit(f - 1, c, p);
    }
  }
  return touches;
}

std::string contact_name(std::size_t step, const Contact& c) {
  return "step " + std::to_string(step) + (c.kind == ContactKind::VertexFace ? " VF " : " EE ") +
         std::to_string(c.a) + "/" + std::to_string(c.b) + " toi " + std::to_string(c.toi);
}

}  // namespace

TEST(CcdTouchCertificate, FoldingClothContactsAreTrueAndNotLate) {
  // The folding cloth's steps (touches in one plane, decided by the certificate and its
  // windows): every contact of every step, checked against the exact reference on its own four
  // points: a true contact, its time of impact not late.
  std::size_t checked = 0;
  const std::uint64_t touches = folding_cloth_contacts([&](std::size_t step, const Contact& c, const CcdPoints& p) {
    const bool vf = c.kind == ContactKind::VertexFace;
    const test::ExactResult ref = vf ? test::exact_vertex_face(p) : test::exact_edge_edge(p);
    ASSERT_TRUE(ref.hit) << contact_name(step, c) << ": no contact in the exact reference";
    ASSERT_TRUE(test::time_not_after(c.toi, ref.toi)) << contact_name(step, c) << ": late";
    ++checked;
  });
  std::cout << "[ folding cloth ] " << checked << " contacts checked exactly, " << touches << " touches certified\n";
  EXPECT_GT(checked, 100u);
  EXPECT_GT(touches, 50u);  // the certificate's paths are exercised
}

TEST(CcdTouchCertificate, FastPathJumpsToTheTouchAsTheSearchWould) {
  // The folding cloth's contacts again: after the fast path, one jump to a touch without the
  // inside functions decides most of them (no search piece); each answer is the search-only
  // path's, its time of impact within 2^-20 of it and not late against the exact reference.
  std::size_t checked = 0, early = 0;
  folding_cloth_contacts([&](std::size_t step, const Contact& c, const CcdPoints& p) {
    const bool vf = c.kind == ContactKind::VertexFace;
    const auto kind = vf ? detail::CcdKind::VertexFace : detail::CcdKind::EdgeEdge;
    CcdCounters counters;
    double toi = -1, toi_s = -1;
    const bool hit = detail::ccd_run(kind, p, toi, {}, &counters, detail::CcdPath::Fast);
    const bool hit_s = detail::ccd_run(kind, p, toi_s, {}, nullptr, detail::CcdPath::SearchOnly);
    ASSERT_TRUE(hit && hit_s) << contact_name(step, c);
    EXPECT_NEAR(toi, toi_s, 0x1p-20) << contact_name(step, c);
    const test::ExactResult ref = vf ? test::exact_vertex_face(p) : test::exact_edge_edge(p);
    EXPECT_TRUE(test::time_not_after(toi, ref.toi)) << contact_name(step, c) << ": late";
    early += counters.touches == 1 && counters.pieces == 0;
    ++checked;
  });
  std::cout << "[ folding cloth ] " << checked << " contacts, " << early << " decided by the fast path's jump\n";
  EXPECT_GT(early, checked / 3);
}

TEST(CcdTouch, InPlaneIsTheExactOrientationTestWithOrWithoutASharedCoordinate) {
  // Points on a coarse grid (many exactly coplanar quadruples, some sharing a coordinate, some
  // in slanted planes): in_plane, with its shortcut for four points with one coordinate equal,
  // says what the exact orientation test says, whenever the first three are not collinear.
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(-2, 2);
  auto point = [&] {
    return mccd::detail::V3<double>{0.375 * pick(rng), 0.375 * pick(rng), 0.375 * pick(rng)};
  };
  int shared = 0, planar = 0;
  for (int i = 0; i < 20000; ++i) {
    mccd::detail::V3<double> a = point(), b = point(), p = point(), x = point();
    if (i % 3 == 0) x.y = b.y = p.y = a.y;  // one coordinate shared by all four
    if (i % 7 == 1) x = i % 2 ? p : a;      // a point that has not moved: in the plane
    if (mccd::detail::touch::normal_axis(a, b, p) < 0) continue;
    using mccd::detail::touch::vec;
    const bool exact = mccd::detail::exact_orient3d(vec(a), vec(b), vec(p), vec(x)) == 0;
    ASSERT_EQ(mccd::detail::touch::in_plane(a, b, p, x), exact) << i;
    shared += mccd::detail::touch::share_coordinate(a, b, p, x);
    planar += exact;
  }
  EXPECT_GT(shared, 1000);
  EXPECT_GT(planar, shared + 100) << "coplanar quadruples in slanted planes too";
}

TEST(CcdTouch, CrossingEstimatesTheRootOfTheQuadratic) {
  // The time where the point crosses the segment's line, estimated from the quadratic w_k with
  // certain opposite end signs (any estimate is sound; a poor one only loses the window): on
  // random quadratics, near-linear ones and ones with a second root just outside the piece,
  // the estimate lies within 2^-30 of the piece's width of the root found by bisection in
  // long double, and inside the piece.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> coef(-1, 1), unit(0, 1);
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    mccd::detail::touch::PointSegment ps;
    ps.planar = true;
    const double r = unit(rng), s2 = i % 3 == 0 ? 1 + 1e-6 * unit(rng) : (i % 3 == 1 ? 1e9 : 1 + 3 * unit(rng));
    const double k = coef(rng);  // k (u - r)(u - s2) in Bernstein form: c0, c1, c2
    ps.q = {{k * r * s2, k * (r * s2 - (r + s2) / 2), k * (1 - r) * (1 - s2)}};
    if (!(std::fabs(ps.q.c[0]) > 1e-12 && std::fabs(ps.q.c[2]) > 1e-12) || (ps.q.c[0] < 0) == (ps.q.c[2] < 0)) continue;
    const double lo = i % 2 ? 0.0 : 0.25, hi = i % 2 ? 1.0 : 0.5;
    const double t = ps.crossing(lo, hi);
    mccd::detail::Bern<2> part;  // the quadratic over [lo, hi]
    const double e = mccd::detail::restrict_to(ps.q, 0.0, lo, hi, part);
    if (!mccd::detail::touch::changes_sign(part, e)) {
      EXPECT_EQ(t, -1) << i;  // no certain sign change on this piece: no estimate
      continue;
    }
    long double a = 0, b = 1;
    const bool neg_first = part.c[0] < 0;
    for (int it = 0; it < 60; ++it) {
      const long double u = (a + b) / 2, v = 1 - u;
      const long double val = part.c[0] * v * v + 2 * (long double)part.c[1] * u * v + part.c[2] * u * u;
      ((val < 0) == neg_first ? a : b) = u;
    }
    const double root = lo + double(a) * (hi - lo);
    ASSERT_GE(t, lo) << i;
    ASSERT_LE(t, hi) << i;
    EXPECT_NEAR(t, root, 0x1p-30 * (hi - lo)) << i;
    ++checked;
  }
  EXPECT_GT(checked, 5000);
}
