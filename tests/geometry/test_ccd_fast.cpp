// The fast path of the elementary CCD tests (geometry/ccd_fast.h) and the min_distance
// shortcut (geometry/ccd_distance.h): their error bounds against exact rationals, their
// decisions against the exact GMP reference on transversal, near-boundary, tangential and
// end-point contacts, agreement with the search alone, and the work they save.
#include <gmpxx.h>
#include <gtest/gtest.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include <mccd/geometry/ccd.h>
#include <mccd/geometry/ccd_detail.h>
#include <mccd/geometry/ccd_fast.h>
#include <mccd/geometry/frame_sequence.h>
#include <mccd/geometry/topology.h>
#include "support/data.h"
#include "support/exact_ccd.h"

using namespace mccd;
using detail::CcdKind;
using detail::CcdPath;
namespace fs = std::filesystem;

namespace {

using Q = mpq_class;

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  int uniform(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(g); }
  double grid(int bits, int range) { return std::ldexp(double(uniform(-range, range)), -bits); }
  Vec3 vec(int bits, int range) { return {grid(bits, range), grid(bits, range), grid(bits, range)}; }
  double time() { return std::ldexp(double(uniform(0, 256)), -8); }
};

CcdPoints moving(const std::array<Vec3, 4>& at_tc, const std::array<Vec3, 4>& v, double tc) {
  CcdPoints p;
  for (int i = 0; i < 4; ++i) p.start[i] = at_tc[i] - v[i] * tc, p.end[i] = at_tc[i] + v[i] * (1 - tc);
  return p;
}

// One query of a family built around an exact contact at a dyadic time tc:
//  0 transversal: VF the vertex through a random interior point of the face, EE two
//    segments crossing at random interior parameters, random velocities;
//  1 near a boundary: the same with the contact point 2^-k inside or outside an edge (VF)
//    or an end (EE), k in [8, 50];
//  2 tangential: a double root of the coplanarity cubic at tc, with the vertex inside the
//    face (VF) or the crossing inside both edges (EE); perturbed by +-2^-k or not;
//  3 two crossings: the vertex crosses the face's plane twice, outside the face the first
//    time (VF); EE: transversal with a contact time of 0 or 1 (left to the search).
CcdPoints family_query(std::uint64_t seed, bool vf, int family, double force_tc = -1) {
  Rng r(seed);
  double tc = family == 3 && !vf ? double(r.uniform(0, 1)) : r.time();
  if (force_tc >= 0) tc = force_tc;
  std::array<Vec3, 4> x, v;
  for (auto& w : v) w = r.vec(5, 64);
  const int k = r.uniform(8, 50);
  const double off = family == 1 ? (r.uniform(0, 1) ? 1.0 : -1.0) * std::ldexp(1.0, -k) : 0.0;
  if (family == 2) {
    const double eps = r.uniform(0, 2) == 0 ? 0.0 : (r.uniform(0, 1) ? 1.0 : -1.0) * std::ldexp(1.0, -k);
    CcdPoints p;
    const double t2 = tc * tc;
    if (vf) {  // face (0,0,0), (1,0,0), (0,1,t); vertex (1/4, 1/4 - tc + t, -tc^2 + (1/4 + tc) t)
      p.start = {Vec3(0.25, 0.25 - tc, -t2 + eps), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
      p.end = {Vec3(0.25, 1.25 - tc, -t2 + 0.25 + tc + eps), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 1)};
    } else {  // a on the x axis; b from (1/2, -1, t) to (1/2, 1 + t, tc^2 - (2 tc + 1) t)
      p.start = {Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, 0), Vec3(0.5, 1, t2 + eps)};
      p.end = {Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0.5, -1, 1), Vec3(0.5, 2, t2 - 2 * tc - 1 + eps)};
    }
    return p;
  }
  if (vf) {
    x[1] = r.vec(6, 64), x[2] = r.vec(6, 64), x[3] = r.vec(6, 64);
    double u = std::ldexp(double(r.uniform(1, 15)), -4), w = (1 - u) * std::ldexp(double(r.uniform(1, 15)), -4);
    if (family == 1) u = off, w = std::ldexp(double(r.uniform(1, 15)), -4);
    x[0] = x[1] * u + x[2] * w + x[3] * (1 - u - w);
    if (family == 3) {
      // Face (0,0,0), (1,0,0), (0,1,t); vertex (1/4, y(t), z(t)) with y = -(r1 + r2)/2 + t:
      // f is proportional to z - t y = -(t - r1)(t - r2), the vertex below the face's edge
      // y = 0 at r1 (no contact) and inside at r2 (the first contact). Shifted off the axes.
      const double r1 = std::ldexp(double(r.uniform(0, 7)), -4), r2 = r1 + std::ldexp(double(r.uniform(1, 8)), -4);
      const double py = -(r1 + r2) / 2, pz = -r1 * r2, vz = (r1 + r2) / 2;
      const Vec3 shift = r.vec(4, 64);
      CcdPoints p;
      p.start = {Vec3(0.25, py, pz), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
      p.end = {Vec3(0.25, py + 1, pz + vz), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 1)};
      for (int i = 0; i < 4; ++i) p.start[i] += shift, p.end[i] += shift;
      return p;
    }
  } else {
    x[0] = r.vec(6, 64), x[1] = r.vec(6, 64);
    const double s = family == 1 ? off : std::ldexp(double(r.uniform(1, 15)), -4);
    const Vec3 c = x[0] + (x[1] - x[0]) * s, dir = r.vec(4, 16);
    const double q = std::ldexp(double(r.uniform(1, 15)), -4);
    x[2] = c - dir * q, x[3] = c + dir * (1 - q);
  }
  return moving(x, v, tc);
}

struct Tally {
  std::atomic<int> queries{0}, positives{0}, fast_decided{0}, fn{0}, late{0}, fast_wrong{0}, coarse{0}, fp_more{0};
};

// Both paths and the exact reference on one query.
void check(const CcdPoints& p, bool vf, Tally& t, const std::string& what) {
  const CcdKind kind = vf ? CcdKind::VertexFace : CcdKind::EdgeEdge;
  CcdCounters c;
  double toi = -1, toi_s = -1;
  const bool hit = detail::ccd_run(kind, p, toi, {}, &c, CcdPath::Fast);
  const bool hit_s = detail::ccd_run(kind, p, toi_s, {}, nullptr, CcdPath::SearchOnly);
  const test::ExactResult ref = vf ? test::exact_vertex_face(p) : test::exact_edge_edge(p);
  ++t.queries;
  t.positives += ref.hit;
  const bool decided = c.fast_hits + c.fast_misses > 0;
  t.fast_decided += decided;
  if (ref.hit && !hit) {
    ++t.fn;
    ADD_FAILURE() << what << ": false negative";
  }
  if (decided && (c.fast_hits > 0) != ref.hit) {
    ++t.fast_wrong;
    ADD_FAILURE() << what << ": the fast path decided " << (c.fast_hits > 0) << ", the exact answer is " << ref.hit;
  }
  if (hit && !ref.hit && !hit_s) ++t.fp_more;
  if (hit && ref.hit) {
    if (!test::time_not_after(toi, ref.toi)) {
      ++t.late;
      ADD_FAILURE() << what << ": toi " << toi << " later than the exact one";
    }
    // A certified contact's toi is within 2^-32 of the root, or at the start of a span where
    // the cubic is within its error bound (near-tangential roots): then not before the
    // search's (the slack covers the checks).
    if (c.fast_hits > 0 && test::time_not_after(toi + 0x1p-31, ref.toi) && toi + 0x1p-31 < toi_s) {
      ++t.coarse;
      ADD_FAILURE() << what << ": fast toi " << toi << " more than 2^-31 before the exact one and the search's "
                    << toi_s;
    }
  }
}

}  // namespace

// The snapshots' error bounds (f within S.ef, g_i within 24 u M_i, N within normal_error)
// against exact rationals, on inputs with heavy cancellation: large offsets, nearly
// coplanar points, tiny and huge scales.
TEST(CcdFastPath, SnapshotBoundsHoldExactly) {
  Rng r(2024);
  int checked = 0;
  for (int i = 0; i < 3000; ++i) {
    const bool vf = i % 2 == 0;
    const double scale = std::ldexp(1.0, r.uniform(-50, 50));
    const Vec3 shift = r.vec(0, 1 << 20) * scale;
    CcdPoints p;
    std::uniform_real_distribution<double> u(-1, 1);
    for (int k = 0; k < 4; ++k) {
      p.start[k] = Vec3(u(r.g), u(r.g), u(r.g) * 1e-9) * scale + shift;
      p.end[k] = Vec3(u(r.g), u(r.g), u(r.g) * 1e-9) * scale + shift;
    }
    detail::Setup<double> S;
    S.kind = vf ? CcdKind::VertexFace : CcdKind::EdgeEdge;
    ASSERT_EQ(detail::load(p, 0, S), detail::Load::Ok);
    detail::coplanarity(S);
    double M[4];
    const int ng = vf ? detail::vertex_face::inside_magnitudes(S, M) : detail::edge_edge::inside_magnitudes(S, M);
    const double eN = vf ? detail::vertex_face::normal_error(S) : detail::edge_edge::normal_error(S);
    const double tau = std::ldexp(double(r.uniform(0, 1 << 20)), -20);
    detail::Snap<double> sn;
    if (vf)
      detail::vertex_face::snapshot(S, tau, sn);
    else
      detail::edge_edge::snapshot(S, tau, sn);
    // Exact values from the (scaled) input doubles.
    auto X = [&](int k, int ax) -> Q { return Q((&S.s[k].x)[ax]) * (1 - Q(tau)) + Q((&S.e[k].x)[ax]) * Q(tau); };
    using V = std::array<Q, 3>;
    auto diff = [&](int a, int b) { return V{X(a, 0) - X(b, 0), X(a, 1) - X(b, 1), X(a, 2) - X(b, 2)}; };
    auto cr = [](const V& a, const V& b) { return V{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; };
    auto dt = [](const V& a, const V& b) { return Q(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]); };
    Q f, g[4];
    V N;
    if (vf) {
      const V A = diff(1, 0), B = diff(2, 0), C = diff(3, 0);
      const V Xc = cr(B, C), Y = cr(C, A), Z = cr(A, B);
      N = V{Xc[0] + Y[0] + Z[0], Xc[1] + Y[1] + Z[1], Xc[2] + Y[2] + Z[2]};
      f = dt(A, Xc), g[0] = dt(N, Xc), g[1] = dt(N, Y), g[2] = dt(N, Z);
    } else {
      const V da = diff(1, 0), db = diff(3, 2), w = diff(2, 0), v = diff(2, 1), z = diff(3, 0);
      N = cr(da, db);
      f = dt(w, N), g[0] = dt(cr(w, db), N), g[1] = -dt(cr(v, db), N), g[2] = dt(cr(w, da), N), g[3] = dt(cr(da, z), N);
    }
    auto within = [](double computed, const Q& exact, double bound) { return abs(Q(computed) - exact) <= Q(bound); };
    EXPECT_TRUE(within(sn.f, f, S.ef)) << "f, case " << i;
    for (int k = 0; k < ng; ++k) EXPECT_TRUE(within(sn.g[k], g[k], M[k] * 24 * detail::kU + 2 * detail::kTiny)) << "g" << k << ", case " << i;
    for (int ax = 0; ax < 3; ++ax) EXPECT_TRUE(within((&sn.N.x)[ax], N[ax], eN)) << "N, case " << i;
    ++checked;
  }
  EXPECT_EQ(checked, 3000);
}

// The helpers: Descartes' rule with uncertain middle coefficients, the power of two above a
// number, and the root estimate.
TEST(CcdFastPath, IsolationHelpers) {
  using B = detail::Bern<3, double>;
  EXPECT_TRUE(detail::one_sign_change(B{{1, 0.5, -0.5, -1}}, 0.1));
  EXPECT_TRUE(detail::one_sign_change(B{{1, 0.05, -0.5, -1}}, 0.1));   // c1 uncertain, c2 < 0 certain
  EXPECT_FALSE(detail::one_sign_change(B{{1, 0.05, 0.05, -1}}, 0.1));  // could be + - + -
  EXPECT_FALSE(detail::one_sign_change(B{{1, -1, 1, -1}}, 0.1));
  EXPECT_FALSE(detail::one_sign_change(B{{0.05, -1, -1, -1}}, 0.1));   // end uncertain
  EXPECT_TRUE(detail::one_sign_change(B{{-1, -0.5, 0.05, 1}}, 0.1));
  EXPECT_FALSE(detail::one_sign_change(B{{1, 0.5, 0.5, 1}}, 0.1));
  EXPECT_EQ(detail::pow2_at_least(0.75), 1.0);
  EXPECT_EQ(detail::pow2_at_least(0x1p-40), 0x1p-40);
  EXPECT_EQ(detail::pow2_at_least(3 * 0x1p-41), 0x1p-39);
  // f = (t - 0.3)(t + 1)(t - 2) = t^3 - 1.3 t^2 - 1.7 t + 0.6: one root in [0, 1].
  const B g{{0.6, 0.6 - 1.7 / 3, 0.6 - 2 * 1.7 / 3 - 1.3 / 3, 0.6 - 1.7 - 1.3 + 1}};
  double slope = 0;
  EXPECT_NEAR(detail::root_estimate(g, 0, 1, slope), 0.3, 1e-14);
  EXPECT_NEAR(slope, 3 * 0.09 - 2.6 * 0.3 - 1.7, 1e-12);
  // The same cubic over the piece [0.25, 0.5]: the estimate is a time in that piece.
  B h;
  detail::restrict_to(g, 0.0, 0.25, 0.5, h);
  EXPECT_NEAR(detail::root_estimate(h, 0.25, 0.5, slope), 0.3, 1e-14);
  EXPECT_NEAR(slope, 3 * 0.09 - 2.6 * 0.3 - 1.7, 1e-12);
  // The search's extended pass locates roots with the same estimate, in long double, on
  // pieces as narrow as its windows: here [0.3 - 2^-40, 0.3 + 2^-41].
  detail::Bern<3, long double> gl, hl;
  for (int k = 0; k < 4; ++k) gl.c[k] = g.c[k];
  const long double lo = 0.3L - 0x1p-40L, hi = 0.3L + 0x1p-41L;
  detail::restrict_to(gl, 0.0L, lo, hi, hl);
  long double slope_l = 0;
  const long double rl = detail::root_estimate(hl, lo, hi, slope_l);
  EXPECT_GT(rl, lo);
  EXPECT_LT(rl, hi);
  EXPECT_NEAR(static_cast<double>(rl - 0.3L), 0.0, 1e-15);
  // One de Casteljau step at s gives the two restrictions, within the stated bounds.
  B l, r, l2, r2;
  const double e = detail::split_at(g, 0x1p-40, 0.375, l, r);
  detail::restrict_to(g, 0.0, 0.0, 0.375, l2);
  detail::restrict_to(g, 0.0, 0.375, 1.0, r2);
  EXPECT_GT(e, 0x1p-40);
  for (int k = 0; k < 4; ++k) {
    EXPECT_NEAR(l.c[k], l2.c[k], e);
    EXPECT_NEAR(r.c[k], r2.c[k], e);
  }
  EXPECT_EQ(l.c[0], g.c[0]);
  EXPECT_EQ(r.c[3], g.c[3]);
  EXPECT_EQ(l.c[3], r.c[0]);
}

// Every family of contacts against the exact reference: no false negative, no late toi, no
// wrong fast decision, a certified toi within 2^-32; the fast path decides most of them
// and never adds a false positive to the search's.
// The few functions the Quad pass needs (the standard library has none for Quad in strict C++),
// checked in exact rationals.
TEST(CcdQuadPass, ScalarHelpers) {
  using detail::Quad;
  auto exact = [](Quad x) -> Q {  // a Quad as a rational: three doubles hold its 113 bits
    const double hi = static_cast<double>(x);
    const double mid = static_cast<double>(x - Quad(hi));
    const double lo = static_cast<double>(x - Quad(hi) - Quad(mid));
    EXPECT_TRUE(Quad(hi) + Quad(mid) + Quad(lo) == x);
    return Q(hi) + Q(mid) + Q(lo);
  };
  EXPECT_TRUE(detail::pow2<Quad>(-100) * detail::pow2<Quad>(100) == Quad(1));
  EXPECT_EQ(exact(detail::pow2<Quad>(-70)), Q(Q(1) / (Q(1) << 70)));
  if (detail::kQuadDigits < 113) GTEST_SKIP() << "Quad is this platform's narrower long double, whose functions are std's";
  const Quad big = detail::pow2<Quad>(100);
  const std::pair<Quad, Quad> floors[] = {
      {Quad(2.5), Quad(2)},           {Quad(-2.5), Quad(-3)},      {Quad(-3), Quad(-3)},
      {Quad(0.25), Quad(0)},          {Quad(-0.25), Quad(-1)},     {big + Quad(0.5), big},
      {-big - Quad(0.5), -big - 1},   {detail::pow2<Quad>(112) * 3, detail::pow2<Quad>(112) * 3}};
  for (const auto& [x, f] : floors) EXPECT_TRUE(detail::floor_(x) == f) << static_cast<double>(x);
  EXPECT_TRUE(detail::fabs_(Quad(-0.75)) == Quad(0.75));
  EXPECT_TRUE(detail::finite_(Quad(1e300) * Quad(1e300)));
  EXPECT_FALSE(detail::finite_(Quad(1e300) * Quad(1e300) * Quad(1e300) * Quad(1e300) * Quad(1e300) * Quad(1e300) *
                               Quad(1e300) * Quad(1e300) * Quad(1e300) * Quad(1e300) * Quad(1e300) * Quad(1e300) *
                               Quad(1e300) * Quad(1e300) * Quad(1e300) * Quad(1e300) * Quad(1e300) * Quad(1e300)));
  EXPECT_TRUE(detail::unit_roundoff<Quad>() == Quad(std::ldexp(1.0, -113)));
  // sqrt_up: never below the square root, and within 2^-55 of it.
  for (const double v : {2.0, 3.0, 0.1, 12345.678, 0x1p-200, 0x1p200}) {
    const Q s = exact(detail::sqrt_up(Quad(v)));
    EXPECT_GE(s * s, Q(v)) << v;
    EXPECT_LE(s * s, Q(v) * (1 + Q(1, 1) / (Q(1) << 55))) << v;
  }
}

TEST(CcdFastPath, ContactFamiliesAgainstExactReference) {
  const int n = std::getenv("MCCD_RANDOM_QUERIES") ? std::atoi(std::getenv("MCCD_RANDOM_QUERIES")) / 5 : 12000;
  Tally fam[4];
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 64), [&](const tbb::blocked_range<int>& rg) {
    for (int i = rg.begin(); i < rg.end(); ++i) {
      const bool vf = i % 2 == 0;
      const int family = (i / 2) % 4;
      const CcdPoints p = family_query(0x2545f4914f6cdd1dull * (i + 7), vf, family);
      check(p, vf, fam[family], "family " + std::to_string(family) + (vf ? " VF" : " EE") + " query " + std::to_string(i));
    }
  });
  const char* names[] = {"transversal", "near a boundary", "tangential", "two crossings / t = 0, 1"};
  for (int f = 0; f < 4; ++f) {
    std::cout << "[ fast    ] " << names[f] << ": " << fam[f].queries << " queries, " << fam[f].positives
              << " positive, " << fam[f].fast_decided << " decided by the fast path\n";
    EXPECT_EQ(fam[f].fn, 0);
    EXPECT_EQ(fam[f].late, 0);
    EXPECT_EQ(fam[f].fast_wrong, 0);
    EXPECT_EQ(fam[f].coarse, 0);
    EXPECT_EQ(fam[f].fp_more, 0);
  }
  // The easy families are the fast path's business; the others must reach it too.
  EXPECT_GT(fam[0].fast_decided.load(), fam[0].queries.load() * 9 / 10);
  EXPECT_GT(fam[1].fast_decided.load(), fam[1].queries.load() / 2);
  EXPECT_GT(fam[0].positives.load(), fam[0].queries.load() * 9 / 10);
  EXPECT_GT(fam[2].positives.load(), fam[2].queries.load() / 3);
  EXPECT_GT(fam[3].fast_decided.load(), fam[3].queries.load() * 4 / 10);  // the VF half
}

// Exact contacts at t = 0 and t = 1 (the cubic vanishes at an end: the search decides) and
// tangential touches: reported, toi never late.
TEST(CcdFastPath, EndpointAndTangentialContacts) {
  Tally t;
  for (int i = 0; i < 800; ++i) {
    const bool vf = i % 2 == 0;
    const double tc = double((i / 2) % 2);
    check(family_query(977 * i + 5, vf, (i / 4) % 2 ? 2 : 0, tc), vf, t, "query " + std::to_string(i) + " at t = " + std::to_string(tc));
  }
  // Built directly: VF with the vertex on the face at t = 0, then at t = 1.
  const Vec3 z(0, 0, 0);
  for (const double tc : {0.0, 1.0}) {
    const CcdPoints vfq = moving({Vec3(0.25, 0.25, 0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
                                 {Vec3(0, 0, 1), z, z, Vec3(0, 0, 0.5)}, tc);
    const CcdPoints eeq = moving({Vec3(-1, 0, 0), Vec3(1, 0, 0), Vec3(0.25, -1, 0), Vec3(0.25, 1, 0)},
                                 {Vec3(0, 0, 1), Vec3(0, 0, 1), z, Vec3(0, 0, -1)}, tc);
    double toi = -1;
    EXPECT_TRUE(vertex_face_ccd(vfq, toi));
    EXPECT_LE(toi, tc);
    EXPECT_GE(toi, tc - 0x1p-12);
    EXPECT_TRUE(edge_edge_ccd(eeq, toi));
    EXPECT_LE(toi, tc);
    EXPECT_GE(toi, tc - 0x1p-12);
    check(vfq, true, t, "VF at t = " + std::to_string(tc));
    check(eeq, false, t, "EE at t = " + std::to_string(tc));
  }
  EXPECT_EQ(t.fn, 0);
  EXPECT_EQ(t.late, 0);
  EXPECT_EQ(t.fast_wrong, 0);
}

// min_distance larger than the scene: every pair is within the distance at t = 0 and is
// reported at toi = 0 without any search piece (this took ~18 us per query before).
TEST(CcdMinDistance, HugeDistanceNeedsNoSearch) {
  Rng r(99);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const double d : {1e30, 1e300, 4.0}) {
    for (const double scale : {1.0, 0x1p-100, 0x1p100}) {
      CcdCounters c;
      int hits = 0, queries = 0;
      for (int i = 0; i < 1000; ++i) {
        CcdPoints p;
        for (int k = 0; k < 4; ++k) {
          p.start[k] = Vec3(u(r.g), u(r.g), u(r.g)) * scale;
          p.end[k] = Vec3(u(r.g), u(r.g), u(r.g)) * scale;
        }
        double toi = -1;
        const CcdOptions o{d * scale};
        hits += (i % 2 ? vertex_face_ccd(p, toi, o, &c) : edge_edge_ccd(p, toi, o, &c)) && toi == 0;
        ++queries;
      }
      EXPECT_EQ(hits, queries) << "d " << d << " scale " << scale;
      EXPECT_LE(c.pieces, std::uint64_t(queries / 100)) << "d " << d << " scale " << scale;
    }
  }
}

// A point crossing a triangle's plane late in the step, far from it at the start: with a
// minimum distance its time is the first within d of the plane (a little before the crossing),
// never later, and not the start of the piece the search decided it on (0 before: the
// crossing is certain on the whole step at once). Edge-edge likewise.
TEST(CcdMinDistance, LateCrossingKeepsItsTime) {
  const Vec3 A(0, 0, 0), B(1, 0, 0), C(0, 1, 0);
  for (const double d : {0x1p-10, 0x1p-20, 1e-3}) {
    for (const double tc : {0.3, 0.7, 0.95}) {
      // the point's height: 0.7 - t scaled so that it is 0 at tc; within d from tc - d / speed
      const double speed = 1.0, z0 = tc * speed;
      CcdPoints vf;
      vf.start = {Vec3(0.2, 0.2, z0), A, B, C};
      vf.end = {Vec3(0.2, 0.2, z0 - speed), A, B, C};
      CcdPoints ee;
      ee.start = {Vec3(-1, 0.3, z0), Vec3(1, 0.3, z0), Vec3(0.2, -1, 0), Vec3(0.2, 1, 0)};
      ee.end = {Vec3(-1, 0.3, z0 - speed), Vec3(1, 0.3, z0 - speed), Vec3(0.2, -1, 0), Vec3(0.2, 1, 0)};
      const double first = tc - d / speed;  // the first time within d
      for (const bool is_vf : {true, false}) {
        double toi = -1;
        const bool hit = is_vf ? vertex_face_ccd(vf, toi, CcdOptions{d}) : edge_edge_ccd(ee, toi, CcdOptions{d});
        const std::string what =
            std::string(is_vf ? "VF" : "EE") + " d " + std::to_string(d) + " tc " + std::to_string(tc);
        EXPECT_TRUE(hit) << what;
        EXPECT_LE(toi, first * (1 + 1e-12)) << what << ": late";
        // (the band of the search bounds d |n| over the whole step: a few d early at most)
        EXPECT_GE(toi, first - 16 * d) << what << ": far earlier than the first time within d";
      }
    }
  }
}

// Each way of proving "within d at t = 0" (corner, segment, interior), for both kinds, at
// half the distance (a contact at toi = 0, no search) and at twice the distance moving apart
// (no contact).
TEST(CcdMinDistance, WithinDistanceAtStart) {
  const double d = 0x1p-8;
  const Vec3 z(0, 0, 0);
  const Vec3 A(0, 0, 0), B(1, 0, 0), C(0, 1, 0);
  struct Case {
    const char* name;
    bool vf;
    std::array<Vec3, 4> x;
    Vec3 dir;  // from the other primitive towards the first point
  };
  const Case cases[] = {
      {"VF corner", true, {Vec3(-1, -1, 1) * (d / 4), A, B, C}, Vec3(-1, -1, 1)},
      {"VF edge", true, {Vec3(0.5, -d / 2, 0), A, B, C}, Vec3(0, -1, 0)},
      {"VF interior", true, {Vec3(0.25, 0.25, d / 2), A, B, C}, Vec3(0, 0, 1)},
      {"EE ends", false, {Vec3(1 + d / 4, 0, 0), Vec3(2, 0, 0), Vec3(1, d / 4, 0), Vec3(1, 2, 0)}, Vec3(1, 0, 0)},
      {"EE end on edge", false, {Vec3(0.5, -d / 2, 0), Vec3(0.5, -1, 0), A, B}, Vec3(0, -1, 0)},
      {"EE interior", false, {Vec3(-1, 0, d / 2), Vec3(1, 0, d / 2), Vec3(0, -1, 0), Vec3(0, 1, 0)}, Vec3(0, 0, 1)},
  };
  for (const Case& k : cases) {
    CcdPoints near;
    near.start = k.x;
    near.end = k.x;
    near.end[0] += Vec3(0.125, 0.125, 0.125);  // moves, so that t = 0 is what decides
    CcdCounters c;
    double toi = -1;
    const CcdOptions o{d};
    const bool hit = k.vf ? vertex_face_ccd(near, toi, o, &c) : edge_edge_ccd(near, toi, o, &c);
    EXPECT_TRUE(hit) << k.name;
    EXPECT_EQ(toi, 0.0) << k.name;
    EXPECT_EQ(c.pieces, 0u) << k.name;
    // Four times farther at the start, and moving away (both points of the first
    // primitive): never within d.
    CcdPoints far = near;
    const Vec3 away = k.dir.normalized() * (3 * d);
    for (int i = 0; i < (k.vf ? 1 : 2); ++i) far.start[i] = k.x[i] + away, far.end[i] = k.x[i] + away * 4;
    if (k.vf || std::string(k.name) != "EE ends") {
      EXPECT_FALSE(k.vf ? vertex_face_ccd(far, toi, o) : edge_edge_ccd(far, toi, o)) << k.name;
    }
  }
  // Within d only later: reported by the search, toi never after the first time within d.
  const CcdPoints later = moving({Vec3(0.25, 0.25, d / 2), A, B, C}, {Vec3(0, 0, 1), z, z, z}, 0.5);
  double toi = -1;
  EXPECT_TRUE(vertex_face_ccd(later, toi, CcdOptions{d}));
  EXPECT_LE(toi, 0.5 - 1.5 * d);  // first within d at 0.5 - 1.5 d
}

// On the real cloth-ball step: the fast path certifies nearly every listed (true) pair,
// with the search's answer; a sample checked against the exact reference.
TEST(CcdFastPath, ClothBallListedPairs) {
  const fs::path dir = test::data_dir() / "toi" / "cloth-ball";
  MCCD_REQUIRE_DATA(dir / "boxes" / "92vf.json");
  const FrameSequence seq =
      read_frames({(dir / "frames" / "cloth_ball92.ply").string(), (dir / "frames" / "cloth_ball93.ply").string()});
  const MeshTopology topo(seq.mesh.num_vertices(), seq.mesh.faces);
  const std::uint64_t nv = topo.num_vertices(), ne = topo.num_edges();
  for (const bool vf : {true, false}) {
    std::ifstream in(dir / "boxes" / (vf ? "92vf.json" : "92ee.json"));
    const nlohmann::json pairs = nlohmann::json::parse(in);
    CcdCounters c;
    Tally t;
    int agree = 0, i = 0;
    for (const auto& pr : pairs) {
      std::array<std::uint32_t, 4> ids;
      if (vf) {
        std::uint64_t v = pr[0], f = pr[1];
        if (v >= nv) std::swap(v, f);
        const Triangle& tri = topo.faces()[f - nv - ne];
        ids = {std::uint32_t(v), tri[0], tri[1], tri[2]};
      } else {
        const Edge& a = topo.edges()[pr[0].get<std::uint64_t>() - nv];
        const Edge& b = topo.edges()[pr[1].get<std::uint64_t>() - nv];
        ids = {a[0], a[1], b[0], b[1]};
      }
      CcdPoints p;
      for (int k = 0; k < 4; ++k) p.start[k] = seq.frames[0].point(ids[k]), p.end[k] = seq.frames[1].point(ids[k]);
      const CcdKind kind = vf ? CcdKind::VertexFace : CcdKind::EdgeEdge;
      double toi = -1, toi_s = -1;
      const bool hit = detail::ccd_run(kind, p, toi, {}, &c, CcdPath::Fast);
      agree += hit == detail::ccd_run(kind, p, toi_s, {}, nullptr, CcdPath::SearchOnly);
      if (i++ % 97 == 0) check(p, vf, t, std::string(vf ? "VF" : "EE") + " pair " + std::to_string(i - 1));
    }
    std::cout << "[ cloth   ] " << (vf ? "VF" : "EE") << ": " << pairs.size() << " listed pairs, " << c.fast_hits
              << " certified by the fast path, " << c.pieces << " search pieces\n";
    EXPECT_EQ(agree, int(pairs.size()));
    EXPECT_GT(c.fast_hits, c.root_tests * 99 / 100);
    EXPECT_EQ(t.fn + t.late + t.fast_wrong + t.coarse, 0);
  }
}
