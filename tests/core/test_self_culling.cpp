// Self-collision culling (core/self_culling.h): which BVH nodes are disks, the certified
// orientation and contour tests, and scenes that report the same contacts with and without it.
#include <mccd/core/bvh.h>
#include <mccd/core/leaf_rule_owners.h>
#include <mccd/parallel/scene.h>
#include <mccd/core/self_culling.h>
#include <mccd/geometry/lane_masks.h>

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include <Eigen/Geometry>

#include <array>
#include <bit>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "fixtures/scenes.h"
#include "fixtures/shapes.h"
#include "generators/meshes.h"
#include "support/simd_levels.h"

using namespace mccd;
using namespace mccd::detail;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// `points` random points in [-1, 1]^3 and where they move in the step: test `n` of a series
/// moves mostly a little, every 5th far, every 7th not at all.
void random_motion(std::mt19937_64& rng, int n, int points, Vec3* p0, Vec3* p1) {
  std::uniform_real_distribution<double> coord(-1, 1), move(-0.6, 0.6);
  for (int k = 0; k < points; ++k) {
    p0[k] = Vec3(coord(rng), coord(rng), coord(rng));
    const double scale = n % 7 == 0 ? 0.0 : n % 5 == 0 ? 3.0 : 0.3;
    p1[k] = p0[k] + scale * Vec3(move(rng), move(rng), move(rng));
  }
}

struct Built {
  SceneFaces faces;
  SceneTopology scene;
  BvhTopology bvh;
  Built(const std::vector<TriMesh>& meshes, unsigned leaf)
      : faces(scene_faces(meshes)), scene(faces, {}, Representatives::Leaf), bvh(make_bvh(meshes, faces, leaf)) {}
  static BvhTopology make_bvh(const std::vector<TriMesh>& meshes, const SceneFaces& f, unsigned leaf) {
    Positions x(f.vertex_offsets.back());
    for (std::size_t m = 0; m < meshes.size(); ++m)
      for (std::size_t v = 0; v < meshes[m].vertices.rows(); ++v)
        x.set_point(f.vertex_offsets[m] + v, meshes[m].vertices.point(v));
    return BvhTopology(triangle_bounds(f.faces, x), BvhBuild::Sah, leaf, f.face_offsets);
  }
};

std::vector<PositionsView> views(const std::vector<Positions>& frame) { return {frame.begin(), frame.end()}; }

/// A strip wound like a ramp of a parking garage, 1.25 turns in 8 segments (16 triangles, one
/// BVH leaf of 16): seen from above it covers part of itself, and every triangle faces up. Its
/// height per turn goes from `pitch0` to `pitch1`.
AnimatedScene spiral_ramp(double pitch0, double pitch1, int frames) {
  const int na = 8, nr = 1;
  const double turns = 1.25;
  TriMesh m;
  auto id = [&](int a, int r) { return static_cast<std::uint32_t>(a * (nr + 1) + r); };
  for (int a = 0; a < na; ++a)
    for (int r = 0; r < nr; ++r) {
      // counter-clockwise seen from above: (angle, radius) is a left-handed chart, so swap
      m.faces.push_back({id(a, r), id(a + 1, r + 1), id(a + 1, r)});
      m.faces.push_back({id(a, r), id(a, r + 1), id(a + 1, r + 1)});
    }
  auto positions = [&](double pitch) {
    Positions p((na + 1) * (nr + 1));
    for (int a = 0; a <= na; ++a)
      for (int r = 0; r <= nr; ++r) {
        const double th = 2 * kPi * turns * a / na, rad = 1.0 + 0.5 * r / nr;
        p.set_point(id(a, r), Vec3(rad * std::cos(th), rad * std::sin(th), pitch * th / (2 * kPi)));
      }
    return p;
  };
  m.vertices = positions(pitch0);
  AnimatedScene s;
  s.meshes = {m};
  for (int f = 0; f < frames; ++f) {
    const double u = double(f) / (frames - 1);
    s.frames.push_back({positions(pitch0 + u * (pitch1 - pitch0))});
  }
  return s;
}

}  // namespace

TEST(SelfCulling, AGridIsADiskAtEveryNodeAndASphereIsNotAtItsRoot) {
  const TriMesh grid = make_grid_mesh(12);  // 12 x 12 quads
  Built g({grid}, 12);
  SelfCulling c(g.bvh, g.scene);
  ASSERT_TRUE(c.disk(0));
  // the root's cycle: the grid's 48 boundary vertices, each once, consecutive ones joined by
  // a boundary edge
  const std::set<std::uint32_t> cycle(c.cycle_begin(0), c.cycle_end(0));
  EXPECT_EQ(c.cycle_end(0) - c.cycle_begin(0), 48);
  EXPECT_EQ(cycle.size(), 48u);
  const MeshTopology& topo = g.scene.topology();
  for (const std::uint32_t* v = c.cycle_begin(0); v != c.cycle_end(0); ++v) {
    const std::uint32_t w = v + 1 == c.cycle_end(0) ? *c.cycle_begin(0) : v[1];
    const std::int64_t e = topo.find_edge(*v, w);
    ASSERT_GE(e, 0);
    EXPECT_EQ(topo.edge_face_count(static_cast<std::size_t>(e)), 1u);
  }
  std::size_t disks = 0;
  for (std::uint32_t n = 0; n < g.bvh.size(); ++n) disks += c.disk(n);
  EXPECT_GT(disks, g.bvh.size() / 2);

  Built s({make_sphere_mesh(8, 16)}, 4);
  SelfCulling cs(s.bvh, s.scene);
  EXPECT_FALSE(cs.disk(0));  // closed: no boundary
  EXPECT_GT(cs.num_disks(), 0u);
  // without self-collision nothing is a candidate
  SceneTopology off(s.faces, {MeshOptions{false, false}}, Representatives::Leaf);
  EXPECT_EQ(SelfCulling(s.bvh, off).num_disks(), 0u);
}

TEST(SelfCulling, APunctureOrAHoleIsNotADisk) {
  // A torus less one triangle has a single boundary cycle (that triangle's edges) but Euler
  // characteristic -1; a grid less its middle quad has two boundary cycles.
  const int nu = 12, nv = 8;
  TriMesh torus;
  torus.vertices = Positions(nu * nv);
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double a = 2 * kPi * i / nu, b = 2 * kPi * j / nv;
      const double r = 2 + std::cos(b);
      torus.vertices.set_point(id(i, j), Vec3(r * std::cos(a), r * std::sin(a), std::sin(b)));
      if (i == 0 && j == 0) {
        torus.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});  // the other half is left out
        continue;
      }
      torus.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      torus.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  Built t({torus}, 16);
  SelfCulling ct(t.bvh, t.scene);
  EXPECT_FALSE(ct.disk(0));
  EXPECT_GT(ct.num_disks(), 0u);

  TriMesh holed = make_grid_mesh(4);  // 4 x 4 quads, two triangles each
  TriMesh kept = holed;
  kept.faces.clear();
  for (const Triangle& f : holed.faces) {
    Vec3 c = Vec3::Zero();
    for (std::uint32_t v : f) c += holed.vertices.point(v) / 3;
    const Vec3 lo = holed.vertices.point(0);
    const Vec3 hi = holed.vertices.point(holed.vertices.rows() - 1);
    const Vec3 mid = (lo + hi) / 2, quad = (hi - lo) / 4;
    // drop the two triangles of the quad just above and right of the middle
    if (c.x() > mid.x() && c.x() < mid.x() + quad.x() && c.y() > mid.y() && c.y() < mid.y() + quad.y()) continue;
    kept.faces.push_back(f);
  }
  ASSERT_EQ(kept.faces.size(), holed.faces.size() - 2);
  Built h({kept}, 16);
  EXPECT_FALSE(SelfCulling(h.bvh, h.scene).disk(0));
  Built whole({holed}, 16);
  EXPECT_TRUE(SelfCulling(whole.bvh, whole.scene).disk(0));
}

TEST(SelfCulling, AClosedSphereIsACandidateAndAGridOrATorusIsNot) {
  Built s({make_sphere_mesh(8, 16)}, 4);
  SelfCulling cs(s.bvh, s.scene);
  EXPECT_EQ(cs.num_closed(), 1u);
  EXPECT_TRUE(cs.closed(0));  // the root: the whole sphere
  EXPECT_TRUE(cs.possible());
  Built g({make_grid_mesh(6)}, 4);
  EXPECT_EQ(SelfCulling(g.bvh, g.scene).num_closed(), 0u);
  // two spheres in one mesh: each component its own candidate (where the tree has a node that
  // is exactly one of them), never their union
  TriMesh two = make_sphere_mesh(6, 12);
  const TriMesh other = make_sphere_mesh(6, 12, 1.0, Vec3(5, 0, 0));
  const auto base = static_cast<std::uint32_t>(two.vertices.rows());
  Positions both(two.vertices.rows() + other.vertices.rows());
  for (std::size_t v = 0; v < two.vertices.rows(); ++v) both.set_point(v, two.vertices.point(v));
  for (std::size_t v = 0; v < other.vertices.rows(); ++v) both.set_point(base + v, other.vertices.point(v));
  for (const Triangle& f : other.faces) two.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
  two.vertices = both;
  Built b({two}, 4);
  SelfCulling cb(b.bvh, b.scene);
  EXPECT_EQ(cb.num_closed(), 2u);
  EXPECT_FALSE(cb.closed(0));
}

TEST(SelfCulling, ADiskOverLeavesThatAreNotIsCertified) {
  // The deforming spheres' first frame (four UV spheres of 22 rings): some SAH leaves are not
  // disks (their triangles meet at single vertices), but nodes above them are. Some of those
  // leaves lie in certified patches (their signs count in their disks').
  const AnimatedScene a = make_scene("spheres", 8, 2);
  Built g(a.meshes, 12);
  SelfCulling c(g.bvh, g.scene);
  std::vector<std::uint32_t> ragged;
  for (std::uint32_t n = 0; n < g.bvh.size(); ++n)
    if (g.bvh.leaf(n) && !c.disk(n)) ragged.push_back(n);
  ASSERT_FALSE(ragged.empty()) << "no leaf of the spheres is ragged: the test needs another scene";
  Positions x(g.faces.vertex_offsets.back());
  for (std::size_t m = 0; m < a.meshes.size(); ++m)
    for (std::size_t v = 0; v < a.meshes[m].vertices.rows(); ++v)
      x.set_point(g.faces.vertex_offsets[m] + v, a.meshes[m].vertices.point(v));
  c.certify(g.bvh, g.scene.topology(), x, x);
  EXPECT_GT(c.certified(), 0u);
  std::size_t covered = 0;
  for (std::uint32_t n : ragged) covered += c.covered(n);
  EXPECT_GT(covered, 0u) << ragged.size() << " ragged leaves, none covered";
}

TEST(SelfCulling, NormalSignsHoldOverTheWholeStepOnly) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // counter-clockwise in the xy plane, still: +z certain, nothing along x or y
  EXPECT_EQ(SelfCulling::normal_signs(a, b, c, a, b, c), 1u << 4);
  // clockwise: -z
  EXPECT_EQ(SelfCulling::normal_signs(a, c, b, a, c, b), 2u << 4);
  // tilting within the step keeps +z when the normal never turns past the plane
  const Vec3 c1(0, 1, 0.5);
  EXPECT_TRUE(SelfCulling::normal_signs(a, b, c, a, b, c1) & (1u << 4));
  // a triangle flipped over during the step (c goes to the other side of ab): no sign
  const Vec3 flipped(0, -1, 0);
  EXPECT_EQ(SelfCulling::normal_signs(a, b, c, a, b, flipped) & (3u << 4), 0u);
  // a triangle that is degenerate at the start: no sign, though it is fine at the end
  EXPECT_EQ(SelfCulling::normal_signs(a, b, Vec3(2, 0, 0), a, b, c) & (3u << 4), 0u);
  // the same orientation at both ends, but b and c turn half a turn about a and meet it
  // halfway (the triangle is a point there): the middle coefficient leaves no sign
  const Vec3 b1(-1, 0, 0), c2(0, -1, 0);
  EXPECT_EQ(SelfCulling::normal_signs(a, b, c, a, b1, c2) & (3u << 4), 0u);
  // the same turn about the middle of the far edge keeps it a proper triangle: +z holds
  EXPECT_TRUE(SelfCulling::normal_signs(a, b, c, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0.2)) & (1u << 4));
}

TEST(SelfCulling, NormalSignsEqualTheAxisByAxisFormulaAndHoldAtSampledTimes) {
  // The reference: each axis on its own, the three Bernstein coefficients of the d component
  // of (b - a) x (c - a) over the step and the sums of their products' magnitudes, each sign
  // certain beyond 2^-49 of that sum (and the sums above 2^-900).
  auto reference = [](const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a1, const Vec3& b1,
                      const Vec3& c1) {
    const Vec3 u0 = b0 - a0, v0 = c0 - a0, u1 = b1 - a1, v1 = c1 - a1;
    unsigned bits = 0;
    for (int d = 0; d < 3; ++d) {
      const int i = (d + 1) % 3, j = (d + 2) % 3;
      auto term = [&](const Vec3& x, const Vec3& y, double& mag) {
        const double p = x[i] * y[j], q = x[j] * y[i];
        mag += std::abs(p) + std::abs(q);
        return p - q;
      };
      double e[3] = {0, 0, 0};
      const double v[3] = {term(u0, v0, e[0]), term(u0, v1, e[1]) + term(u1, v0, e[1]), term(u1, v1, e[2])};
      bool pos = true, neg = true, normal = true;
      for (int k = 0; k < 3; ++k) {
        pos = pos && v[k] > 0x1p-49 * e[k];
        neg = neg && v[k] < -0x1p-49 * e[k];
        normal = normal && e[k] > 0x1p-900;
      }
      if (normal && pos) bits |= 1u << (2 * d);
      if (normal && neg) bits |= 2u << (2 * d);
    }
    return bits;
  };
  std::mt19937_64 rng(11);
  int signed_axes = 0;
  for (int n = 0; n < 20000; ++n) {
    Vec3 p0[3], p1[3];
    random_motion(rng, n, 3, p0, p1);
    if (n % 11 == 0) p0[2] = p0[0] + 0.5 * (p0[1] - p0[0]);  // collinear at the start
    const unsigned bits = SelfCulling::normal_signs(p0[0], p0[1], p0[2], p1[0], p1[1], p1[2]);
    ASSERT_EQ(bits, reference(p0[0], p0[1], p0[2], p1[0], p1[1], p1[2])) << n;
    for (unsigned wanted : {0x03u, 0x0Cu, 0x30u, 0x15u})
      ASSERT_EQ(SelfCulling::normal_signs(p0[0], p0[1], p0[2], p1[0], p1[1], p1[2], wanted), bits & wanted) << n;
    // A certain sign holds at every sampled time (the normal evaluated in long double).
    for (int d = 0; d < 3; ++d) {
      if (!(bits >> (2 * d) & 3u)) continue;
      ++signed_axes;
      const long double want = (bits >> (2 * d) & 1u) ? 1 : -1;
      const int i = (d + 1) % 3, j = (d + 2) % 3;
      for (int s = 0; s <= 64; ++s) {
        const long double t = s / 64.0L;
        long double q[3][3];
        for (int k = 0; k < 3; ++k)
          for (int a = 0; a < 3; ++a) q[k][a] = (1 - t) * p0[k][a] + t * p1[k][a];
        const long double n_d = (q[1][i] - q[0][i]) * (q[2][j] - q[0][j]) - (q[1][j] - q[0][j]) * (q[2][i] - q[0][i]);
        ASSERT_GT(want * n_d, 0) << n << " axis " << d << " t " << static_cast<double>(t);
      }
    }
  }
  EXPECT_GT(signed_axes, 10000);  // the check above is not vacuous
}

TEST(SelfCulling, CornersInLeafOrderCertifyTheSame) {
  // certify() reading each triangle's corners from a copy in the leaves' order (the leaf
  // rule's LeafOwnership::face_corners; a closed surface's read in place there) against
  // reading them through the mesh: the same nodes covered, by the same certified node, step
  // after step of the generated cloth (disks) and of the spheres (closed surfaces).
  for (const char* name : {"cloth", "spheres"}) {
    const AnimatedScene a = make_scene(name, 8, 4);
    Built g(a.meshes, 21);
    const LeafOwnership owners(g.bvh, g.scene.topology());
    ASSERT_NE(owners.face_corners_in_order(), nullptr);
    SelfCulling plain(g.bvh, g.scene), ordered(g.bvh, g.scene);
    ASSERT_GT(plain.num_disks() + plain.num_closed(), 0u) << name;
    std::uint64_t certified = 0;
    for (std::size_t f = 0; f + 1 < a.frames.size(); ++f) {
      Positions x0(g.scene.topology().num_vertices()), x1(x0.rows());  // every mesh's, in scene order
      std::size_t at = 0;
      for (std::size_t m = 0; m < a.meshes.size(); ++m)
        for (std::size_t v = 0; v < a.frames[f][m].rows(); ++v, ++at) {
          x0.set_point(at, a.frames[f][m].point(v));
          x1.set_point(at, a.frames[f + 1][m].point(v));
        }
      plain.certify(g.bvh, g.scene.topology(), x0, x1);
      ordered.certify(g.bvh, g.scene.topology(), x0, x1, serial_executor(), {}, owners.face_corners_in_order());
      ASSERT_EQ(plain.certified(), ordered.certified()) << name << " step " << f;
      certified += plain.certified();
      for (std::uint32_t n = 0; n < g.bvh.size(); ++n)
        for (std::uint32_t m : {0u, n / 2, n})
          ASSERT_EQ(plain.covers(n, m), ordered.covers(n, m)) << name << " step " << f << " nodes " << n << ", " << m;
    }
    EXPECT_GT(certified, 0u) << name;
  }
}

TEST(SelfCulling, ContourTestsFollowTheMotion) {
  // a square in the xy plane, then the same square with one corner moved across the opposite
  // edge by the end of the step
  Positions x0({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(0.5, 0.5, 0)});
  const std::uint32_t square[] = {0, 1, 2, 3};
  EXPECT_TRUE(SelfCulling::contour_simple(square, square + 4, 2, x0, x0));
  // seen along x or y it is a segment: not simple
  EXPECT_FALSE(SelfCulling::contour_simple(square, square + 4, 0, x0, x0));
  Positions x1 = x0;
  x1.set_point(2, Vec3(-0.5, 1, 0));  // corner 2 ends beyond edge 3 -> 0
  EXPECT_FALSE(SelfCulling::contour_simple(square, square + 4, 2, x0, x1));
  // a bow tie: 0 1 3 2 crosses itself
  const std::uint32_t bow[] = {0, 1, 3, 2};
  EXPECT_FALSE(SelfCulling::contour_simple(bow, bow + 4, 2, x0, x0));
  // a long zigzag boundary whose non-neighbouring edges' boxes touch but a line separates
  // them: simple
  // (a staircase of unit steps, as a grid's patches have, and the same one 3 higher)
  Positions z(20);
  std::vector<std::uint32_t> zig;
  for (int i = 0; i < 10; ++i) {
    z.set_point(static_cast<std::size_t>(i), Vec3((i + 1) / 2, i % 2, 0));
    z.set_point(static_cast<std::size_t>(19 - i), Vec3((i + 1) / 2, 3 + i % 2, 0));
  }
  for (std::uint32_t i = 0; i < 20; ++i) zig.push_back(i);
  EXPECT_TRUE(SelfCulling::contour_simple(zig.data(), zig.data() + zig.size(), 2, z, z));
  // the spiral ramp's whole boundary seen from above covers itself
  const AnimatedScene ramp = spiral_ramp(0.4, 0.4, 2);
  Built b(ramp.meshes, 16);
  ASSERT_TRUE(b.bvh.leaf(0));
  SelfCulling c(b.bvh, b.scene);
  ASSERT_TRUE(c.disk(0));
  EXPECT_FALSE(SelfCulling::contour_simple(c.cycle_begin(0), c.cycle_end(0), 2, ramp.frames[0][0], ramp.frames[0][0]));
}

TEST(SelfCulling, ASpiralRampThatCollapsesIsNotCulled) {
  // Every triangle of the ramp faces up through the step, so only the contour test keeps
  // the ramp (one leaf) from being certified; its upper turn passes through the lower one.
  // Beside it a flat grid, certified every step, keeps culling busy.
  const AnimatedScene ramp = spiral_ramp(0.4, -0.3, 4);
  AnimatedScene a = ramp;
  TriMesh grid = make_grid_mesh(8, 1.0);
  for (std::size_t v = 0; v < grid.vertices.rows(); ++v) grid.vertices(v, 2) = 5.0;
  a.meshes.push_back(grid);
  for (auto& f : a.frames) f.push_back(grid.vertices);
  SceneOptions on, off;
  on.leaf_size = off.leaf_size = 16;
  off.self_culling = false;
  for (Method m : {Method::Traverse, Method::Phc, Method::Fbd}) {
    Scene s(a.meshes, on), plain(a.meshes, off);
    std::uint64_t contacts = 0, certified = 0;
    for (std::size_t f = 1; f < a.frames.size(); ++f) {
      const StepResult r = s.advance(views(a.frames[f]), m);
      const StepResult p = plain.advance(views(a.frames[f]), Method::BruteForce);
      ASSERT_EQ(r.contacts, p.contacts) << to_string(m) << " step " << f;
      EXPECT_EQ(p.stats.culled_patches, 0u);
      contacts += r.contacts.size();
      certified += r.stats.culled_patches;
    }
    EXPECT_GT(contacts, 0u);
    EXPECT_GT(certified, 0u) << "the grid is certified";
  }
}

TEST(SelfCulling, GeneratedScenesReportTheContactsOfBruteForce) {
  // Every method with culling, step by step, against brute force (which never culls), and
  // fbd against fbd without culling.
  for (const char* name : {"spheres", "cloth", "drape", "tube"}) {
    const AnimatedScene a = make_scene(name, 2, 8);
    SceneOptions off;
    off.self_culling = false;
    Scene plain(a.meshes, off);
    Scene fbd(a.meshes), phc(a.meshes), trav(a.meshes), brute(a.meshes);
    std::uint64_t certified = 0, culled = 0;
    for (std::size_t f = 1; f < a.frames.size(); ++f) {
      const StepResult p = plain.advance(views(a.frames[f]));
      const StepResult r = fbd.advance(views(a.frames[f]));
      ASSERT_EQ(r.contacts, p.contacts) << name << " step " << f;
      EXPECT_EQ(r.earliest_toi, p.earliest_toi) << name << " step " << f;
      ASSERT_EQ(phc.advance(views(a.frames[f]), Method::Phc).contacts, p.contacts) << name << " step " << f;
      ASSERT_EQ(trav.advance(views(a.frames[f]), Method::Traverse).contacts, p.contacts) << name << " step " << f;
      ASSERT_EQ(brute.step(views(a.frames[f - 1]), views(a.frames[f]), Method::BruteForce).contacts, p.contacts)
          << name << " step " << f;
      EXPECT_EQ(p.stats.culled_patches + p.stats.culled_nodes, 0u);
      certified += r.stats.culled_patches;
      culled += r.stats.culled_nodes;
    }
    EXPECT_GT(certified, 0u) << name;
    if (std::string(name) == "spheres") {
      EXPECT_GT(culled, 0u) << name;
    }
  }
}

namespace {

/// Point v of interleaved positions.
Vec3 point(const std::vector<double>& x, std::uint32_t v) { return Vec3(x[3 * v], x[3 * v + 1], x[3 * v + 2]); }

}  // namespace

TEST(SelfCulling, NormalSignsInLanesAreTheScalarSignsAtEveryLevel) {
  // Triangles that keep their normal's signs, that turn during the step, that are nearly
  // axis-aligned (a component near 0), over scales from 2^-60 to 2^60 and one whose scale is
  // below the bound's, at every SIMD level of this processor, in batches of every length.
  const std::vector<const LaneKernels*> levels = test::available_levels();
  ASSERT_GE(levels.size(), 2u);
  std::mt19937_64 rng(777);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> ex(-60, 60);
  constexpr std::size_t kTriangles = 3000, kSmall = kTriangles - 4;
  std::vector<double> x0(9 * kTriangles), x1(9 * kTriangles);
  std::vector<std::array<std::uint32_t, 3>> corners(kTriangles);
  for (std::size_t t = 0; t < kTriangles; ++t) {
    const double s = t == kSmall ? 0x1p-460 : std::ldexp(1.0, ex(rng));
    const int kind = static_cast<int>(t % 4);
    Vec3 p0[3];
    for (int k = 0; k < 3; ++k) {
      p0[k] = Vec3(u(rng), u(rng), u(rng));
      if (kind == 2) p0[k].z() = 1e-14 * u(rng);  // nearly in the plane z = 0
    }
    // nearly a segment: c - a close to a multiple of b - a, every normal component near its
    // rounding bound (decided by the bound's exact magnitude)
    if (kind == 3) p0[2] = p0[0] + u(rng) * (p0[1] - p0[0]) + std::ldexp(u(rng), -47) * Vec3(u(rng), u(rng), u(rng));
    for (int k = 0; k < 3; ++k) {
      const double move = kind == 3 ? std::ldexp(1.0, -47) : 0.05;
      const Vec3 p1 = kind == 1 ? Vec3(-p0[k]) : Vec3(p0[k] + move * Vec3(u(rng), u(rng), u(rng)));
      for (int c = 0; c < 3; ++c) {
        x0[9 * t + 3 * k + c] = p0[k][c] * s;
        x1[9 * t + 3 * k + c] = p1[c] * s;
      }
      corners[t][k] = static_cast<std::uint32_t>(3 * t + k);
    }
  }
  std::vector<std::uint8_t> expected(kTriangles);
  int axes_signed = 0, none = 0;
  for (std::size_t t = 0; t < kTriangles; ++t) {
    const auto& c = corners[t];
    expected[t] = static_cast<std::uint8_t>(SelfCulling::normal_signs(
        point(x0, c[0]), point(x0, c[1]), point(x0, c[2]), point(x1, c[0]), point(x1, c[1]), point(x1, c[2])));
    axes_signed += std::popcount(unsigned(expected[t]));
    none += expected[t] == 0;
  }
  EXPECT_GT(axes_signed, 2000);
  EXPECT_GT(none, 300);
  EXPECT_EQ(expected[kSmall], 0);
  const auto* ids = reinterpret_cast<const std::uint32_t(*)[3]>(corners.data());
  for (const LaneKernels* k : levels) {
    std::vector<std::uint8_t> got(kTriangles + 1, 0xEE);
    SelfCulling::normal_signs_in_lanes(*k, x0.data(), x1.data(), ids, kTriangles, got.data());
    for (std::size_t t = 0; t < kTriangles; ++t)
      ASSERT_EQ(int(got[t]), int(expected[t])) << to_string(k->level) << " triangle " << t;
    EXPECT_EQ(got[kTriangles], 0xEE) << "written past the last triangle";
    for (std::size_t n = 1; n <= 37; ++n) {
      std::vector<std::uint8_t> part(n + 1, 0xEE);
      const unsigned shared = SelfCulling::normal_signs_in_lanes(*k, x0.data(), x1.data(), ids + 7, n, part.data());
      unsigned all = 0x3F;
      for (std::size_t t = 0; t < n; ++t) {
        ASSERT_EQ(int(part[t]), int(expected[7 + t])) << to_string(k->level) << " n " << n;
        all &= expected[7 + t];
      }
      EXPECT_EQ(part[n], 0xEE);
      // the bits they share, returned, with or without the triangles' own
      EXPECT_EQ(shared, all) << to_string(k->level) << " n " << n;
      EXPECT_EQ(SelfCulling::normal_signs_in_lanes(*k, x0.data(), x1.data(), ids + 7, n, nullptr), all);
    }
    EXPECT_EQ(SelfCulling::normal_signs_in_lanes(*k, x0.data(), x1.data(), ids, 0, nullptr), 0x3Fu);
    // Runs of triangles that share signs (those with a certain positive z, then with a certain
    // negative x as well), of every length to past three registers: the shared bits are theirs,
    // not 0.
    for (const unsigned want : {1u << 4, (1u << 4) | (2u << 0)}) {
      std::vector<std::array<std::uint32_t, 3>> same;
      for (std::size_t t = 0; t < kTriangles; ++t)
        if ((expected[t] & want) == want) same.push_back(corners[t]);
      ASSERT_GT(same.size(), 40u);
      const auto* sids = reinterpret_cast<const std::uint32_t(*)[3]>(same.data());
      for (std::size_t n = 1; n <= 40; ++n) {
        unsigned all = 0x3F;
        for (std::size_t t = 0; t < n; ++t) {
          const auto& c = same[t];
          all &= SelfCulling::normal_signs(point(x0, c[0]), point(x0, c[1]), point(x0, c[2]), point(x1, c[0]),
                                           point(x1, c[1]), point(x1, c[2]));
        }
        ASSERT_EQ(all & want, want);
        EXPECT_EQ(SelfCulling::normal_signs_in_lanes(*k, x0.data(), x1.data(), sids, n, nullptr), all)
            << to_string(k->level) << " n " << n;
      }
    }
  }
}

TEST(SelfCulling, StarSignsInLanesAreTheScalarSignsAtEveryLevel) {
  // Triangles around a moving point: facing it (a certain sign either way), nearly edge-on or
  // turning during the step (0), over scales from 2^-60 to 2^60, and one facing triangle whose
  // scale is below the bound's (0, though its values are clear); at every SIMD level of this
  // processor, in batches of every length.
  const std::vector<const LaneKernels*> levels = test::available_levels();
  ASSERT_GE(levels.size(), 2u);
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> ex(-60, 60);
  constexpr std::size_t kTriangles = 3000, kSmall = kTriangles - 4;  // facing, its scale below the bound's
  std::vector<double> x0(9 * kTriangles), x1(9 * kTriangles);
  std::vector<std::array<std::uint32_t, 3>> corners(kTriangles);
  for (std::size_t t = 0; t < kTriangles; ++t) {
    const double s = t == kSmall ? 0x1p-450 : std::ldexp(1.0, ex(rng));
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const int kind = static_cast<int>(t % 4);
    for (int k = 0; k < 3; ++k) {
      // corners on a plane at distance 1 along dir (kind 0, 1), nearly through the centre
      // (kind 2), or crossing it during the step (kind 3)
      Vec3 tangent = Vec3(u(rng), u(rng), u(rng));
      tangent -= tangent.dot(dir) * dir;
      const Vec3 p0 = (kind == 2 ? 1e-13 : 1.0) * dir + tangent;
      const Vec3 p1 = kind == 3 ? Vec3(-0.5 * dir + tangent) : Vec3(p0 + 0.1 * Vec3(u(rng), u(rng), u(rng)));
      for (int c = 0; c < 3; ++c) {
        x0[9 * t + 3 * k + c] = p0[c] * s;
        x1[9 * t + 3 * k + c] = p1[c] * s;
      }
      corners[t][k] = static_cast<std::uint32_t>(3 * t + k);
    }
    if (kind == 1) std::swap(corners[t][1], corners[t][2]);  // the other orientation
  }
  const double m0[3] = {0.001, -0.002, 0.003}, m1[3] = {0.0012, -0.0018, 0.0031};
  std::vector<std::int8_t> expected(kTriangles);
  int counts[3] = {0, 0, 0};
  for (std::size_t t = 0; t < kTriangles; ++t) {
    const auto& c = corners[t];
    expected[t] = static_cast<std::int8_t>(SelfCulling::star_sign(
        point(x0, c[0]), point(x0, c[1]), point(x0, c[2]), Vec3(m0[0], m0[1], m0[2]), point(x1, c[0]),
        point(x1, c[1]), point(x1, c[2]), Vec3(m1[0], m1[1], m1[2])));
    ++counts[expected[t] + 1];
  }
  EXPECT_GT(counts[0], 400);  // -1
  EXPECT_GT(counts[1], 800);  // 0
  EXPECT_GT(counts[2], 400);  // +1
  EXPECT_EQ(expected[kSmall], 0);
  const auto* ids = reinterpret_cast<const std::uint32_t(*)[3]>(corners.data());
  for (const LaneKernels* k : levels) {
    std::vector<std::int8_t> got(kTriangles + 1, 7);
    SelfCulling::star_signs(*k, x0.data(), x1.data(), ids, kTriangles, m0, m1, got.data());
    for (std::size_t t = 0; t < kTriangles; ++t)
      ASSERT_EQ(got[t], expected[t]) << to_string(k->level) << " triangle " << t;
    EXPECT_EQ(got[kTriangles], 7) << "written past the last triangle";
    for (std::size_t n = 1; n <= 37; ++n) {  // every tail length, from an odd start
      std::vector<std::int8_t> part(n + 1, 7);
      SelfCulling::star_signs(*k, x0.data(), x1.data(), ids + 5, n, m0, m1, part.data());
      for (std::size_t t = 0; t < n; ++t) ASSERT_EQ(part[t], expected[5 + t]) << to_string(k->level) << " n " << n;
      EXPECT_EQ(part[n], 7);
    }
  }
}

TEST(SelfCulling, StarSignsHoldAtSampledTimesAndFailWhereTheOrientationTurns) {
  // det(b - a, c - a, p - a) over the step, exactly in long double at 65 times: wherever
  // star_sign names a sign, every sample has it (not a proof, a check of the coefficients).
  auto det = [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
    const long double u[3] = {(long double)b[0] - a[0], (long double)b[1] - a[1], (long double)b[2] - a[2]};
    const long double v[3] = {(long double)c[0] - a[0], (long double)c[1] - a[1], (long double)c[2] - a[2]};
    const long double w[3] = {(long double)p[0] - a[0], (long double)p[1] - a[1], (long double)p[2] - a[2]};
    return u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
  };
  std::mt19937_64 rng(5);
  int certain = 0, uncertain = 0;
  for (int n = 0; n < 20000; ++n) {
    Vec3 q0[4], q1[4];
    random_motion(rng, n, 4, q0, q1);
    const int s = SelfCulling::star_sign(q0[0], q0[1], q0[2], q0[3], q1[0], q1[1], q1[2], q1[3]);
    (s ? certain : uncertain) += 1;
    if (!s) continue;
    for (int i = 0; i <= 64; ++i) {
      const double t = i / 64.0;
      Vec3 q[4];
      for (int k = 0; k < 4; ++k) q[k] = (1 - t) * q0[k] + t * q1[k];
      const long double d = det(q[0], q[1], q[2], q[3]);
      ASSERT_TRUE(s > 0 ? d > 0 : d < 0) << n << " t " << t;
    }
  }
  EXPECT_GT(certain, 10000);
  EXPECT_GT(uncertain, 100);
  // a point passing through the triangle's plane, and one on it at the start: no sign
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(SelfCulling::star_sign(a, b, c, Vec3(0.2, 0.2, 1), a, b, c, Vec3(0.2, 0.2, -1)), 0);
  EXPECT_EQ(SelfCulling::star_sign(a, b, c, Vec3(5, 5, 0), a, b, c, Vec3(5, 5, 1)), 0);
  EXPECT_EQ(SelfCulling::star_sign(a, b, c, Vec3(0.2, 0.2, 1), a, b, c, Vec3(3, 3, 0.1)), 1);
  EXPECT_EQ(SelfCulling::star_sign(a, c, b, Vec3(0.2, 0.2, 1), a, c, b, Vec3(3, 3, 0.1)), -1);
}

TEST(SelfCulling, StarSignsHoldThroughLargeTurns) {
  // A rigid turn by angle a about an axis through the viewpoint scales det(b - a, c - a, p - a)
  // by a quadratic whose middle Bernstein coefficient is cos a: past 120 degrees the cubic's
  // own coefficients disagree, but it keeps its sign up to 180 (split at t = 1/2, star_sign
  // names it). Triangles around a moving point, turned by 10 to 179.9 degrees: every sign
  // named, right at 65 sampled times (in long double), and the lanes' signs at every SIMD
  // level are the scalar ones; a half turn flattens the triangle onto the axis mid-step (no
  // sign).
  const std::vector<const LaneKernels*> levels = test::available_levels();
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  const Vec3 p0(0.1, 0.2, -0.3), p1(0.4, -0.1, 0.2);
  constexpr std::size_t kTriangles = 600;
  std::vector<double> x0(9 * kTriangles), x1(9 * kTriangles);
  std::vector<std::array<std::uint32_t, 3>> corners(kTriangles);
  std::vector<double> angles(kTriangles);
  for (std::size_t t = 0; t < kTriangles; ++t) {
    angles[t] = t + 1 == kTriangles ? 180 : 10 + 169.9 * double(t) / (kTriangles - 2);
    const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Eigen::AngleAxisd turn(angles[t] * kPi / 180, axis);
    // a small triangle facing away from the point, at distance 1 from it
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Vec3 e1 = dir.unitOrthogonal(), e2 = dir.cross(e1);
    const Vec3 local[3] = {dir, dir + 0.2 * e1, dir + 0.2 * e2};
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = p0 + local[k], b = p1 + turn * local[k];
      for (int c = 0; c < 3; ++c) x0[9 * t + 3 * k + c] = a[c], x1[9 * t + 3 * k + c] = b[c];
      corners[t][k] = static_cast<std::uint32_t>(3 * t + k);
    }
  }
  auto point = [](const std::vector<double>& x, std::uint32_t v) { return Vec3(x[3 * v], x[3 * v + 1], x[3 * v + 2]); };
  std::vector<std::int8_t> expected(kTriangles);
  for (std::size_t t = 0; t < kTriangles; ++t) {
    const auto& c = corners[t];
    Vec3 q0[4] = {point(x0, c[0]), point(x0, c[1]), point(x0, c[2]), p0};
    Vec3 q1[4] = {point(x1, c[0]), point(x1, c[1]), point(x1, c[2]), p1};
    const int s = SelfCulling::star_sign(q0[0], q0[1], q0[2], q0[3], q1[0], q1[1], q1[2], q1[3]);
    expected[t] = static_cast<std::int8_t>(s);
    if (angles[t] == 180) {
      EXPECT_EQ(s, 0) << "turned by " << angles[t] << " degrees";
      continue;
    }
    ASSERT_NE(s, 0) << "turned by " << angles[t] << " degrees";
    for (int i = 0; i <= 64; ++i) {
      const long double tt = i / 64.0L;
      long double q[4][3];
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 3; ++d) q[k][d] = (1 - tt) * (long double)q0[k][d] + tt * (long double)q1[k][d];
      long double w[3][3];
      for (int k = 0; k < 3; ++k)
        for (int d = 0; d < 3; ++d) w[k][d] = (k < 2 ? q[k + 1][d] : q[3][d]) - q[0][d];
      const long double det = w[0][0] * (w[1][1] * w[2][2] - w[1][2] * w[2][1]) +
                              w[0][1] * (w[1][2] * w[2][0] - w[1][0] * w[2][2]) +
                              w[0][2] * (w[1][0] * w[2][1] - w[1][1] * w[2][0]);
      ASSERT_TRUE(s > 0 ? det > 0 : det < 0) << "turned by " << angles[t] << " degrees, t " << double(tt);
    }
  }
  const double m0[3] = {p0[0], p0[1], p0[2]}, m1[3] = {p1[0], p1[1], p1[2]};
  const auto* ids = reinterpret_cast<const std::uint32_t(*)[3]>(corners.data());
  for (const LaneKernels* k : levels) {
    std::vector<std::int8_t> got(kTriangles);
    SelfCulling::star_signs(*k, x0.data(), x1.data(), ids, kTriangles, m0, m1, got.data());
    for (std::size_t t = 0; t < kTriangles; ++t)
      ASSERT_EQ(got[t], expected[t]) << to_string(k->level) << " triangle " << t << ", " << angles[t] << " degrees";
  }
}

namespace {
/// One closed mesh moving from its vertices to `x1`: the contacts with culling (every method)
/// equal brute force's; returns the patches certified by fbd.
std::uint64_t closed_step(const TriMesh& m, const Positions& x1) {
  SceneOptions o;
  o.leaf_size = 4;
  std::uint64_t certified = 0;
  for (Method method : {Method::Traverse, Method::Phc, Method::Fbd}) {
    Scene s({m}, o), brute({m});
    const StepResult r = s.advance({PositionsView(x1)}, method);
    const StepResult p = brute.step({PositionsView(m.vertices)}, {PositionsView(x1)}, Method::BruteForce);
    EXPECT_EQ(r.contacts, p.contacts) << to_string(method);
    if (method == Method::Fbd) certified = r.stats.culled_patches;
  }
  return certified;
}
}  // namespace

TEST(SelfCulling, AClosedSurfaceIsCertifiedWholeOnlyWhileStarShaped) {
  const TriMesh ball = make_sphere_mesh(10, 20);
  // pulsating and drifting: certified whole (one patch, the root)
  Positions x1(ball.vertices.rows());
  for (std::size_t v = 0; v < x1.rows(); ++v) {
    const Vec3 p = ball.vertices.point(v);
    x1.set_point(v, Vec3(0.3, -0.2, 0.1) + (1.0 + 0.1 * std::sin(4 * p.x() + 3 * p.z())) * p);
  }
  Scene s({ball});
  const StepResult r = s.advance({PositionsView(x1)});
  EXPECT_EQ(r.stats.culled_patches, 1u);
  EXPECT_EQ(r.stats.leaf_pairs, 0u);  // every leaf pair of the ball lies under the root
  EXPECT_EQ(closed_step(ball, x1), 1u);
  // the top cap pushed down through the bottom: it collides with itself, so it must not be
  // certified whole, and every contact is found
  Positions dent(ball.vertices.rows());
  for (std::size_t v = 0; v < dent.rows(); ++v) {
    const Vec3 p = ball.vertices.point(v);
    dent.set_point(v, p.z() > 0.6 ? Vec3(p.x(), p.y(), p.z() - 1.9) : p);
  }
  SceneOptions o;
  o.leaf_size = 4;
  Scene plain({ball}, o);
  const StepResult d = plain.advance({PositionsView(dent)});
  EXPECT_GT(d.contacts.size(), 0u);
  EXPECT_GT(d.stats.leaf_pairs, 0u);
  closed_step(ball, dent);
  // bent into a C (its centre of mass outside it): not star-shaped from there, not certified
  // whole, though its disks may be
  Positions bent(ball.vertices.rows());
  for (std::size_t v = 0; v < bent.rows(); ++v) {
    const Vec3 p = ball.vertices.point(v);
    const double a = 1.4 * p.x();  // the x axis wound around a circle of radius 1.5
    bent.set_point(v, Vec3((1.5 + 0.4 * p.y()) * std::sin(a), (1.5 + 0.4 * p.y()) * std::cos(a), 0.4 * p.z()));
  }
  Scene b({ball}, o);
  EXPECT_GT(b.advance({PositionsView(bent)}).stats.leaf_pairs, 0u);
  closed_step(ball, bent);
}

TEST(SelfCulling, AClosedSurfaceSpinningFastIsCertifiedWhole) {
  // A rigid ball (and a cone) turned by 150 degrees in one step while drifting, as the
  // n-body scene's bodies spin: every triangle keeps its orientation seen from the moving
  // centre (the split cubic), so it is certified whole, its leaf pairs skipped, and every
  // method still reports brute force's contacts.
  const Eigen::AngleAxisd turn(150 * kPi / 180, Vec3(0.3, -0.5, 0.8).normalized());
  for (const TriMesh& body : {make_sphere_mesh(10, 20), gen::make_cone(24, 0.5, 1.2)}) {
    Vec3 mean = Vec3::Zero();
    for (std::size_t v = 0; v < body.vertices.rows(); ++v) mean += body.vertices.point(v);
    mean /= double(body.vertices.rows());
    Positions x1(body.vertices.rows());
    for (std::size_t v = 0; v < x1.rows(); ++v)
      x1.set_point(v, mean + Vec3(0.2, 0.1, -0.3) + turn * (body.vertices.point(v) - mean));
    Scene s({body});
    const StepResult r = s.advance({PositionsView(x1)});
    EXPECT_EQ(r.stats.culled_patches, 1u) << body.vertices.rows() << " vertices";
    EXPECT_EQ(r.stats.leaf_pairs, 0u);
    EXPECT_TRUE(r.contacts.empty());
    EXPECT_EQ(closed_step(body, x1), 1u);
  }
}

TEST(SelfCulling, AClosedSurfaceThatRepeatsKeepsItsLastOutcome) {
  // certify() given `repeats`: a closed surface said to repeat the last call keeps that call's
  // outcome without computing it (the caller promises the same positions, so it is the same);
  // without `repeats` it is computed again, and that outcome is what the next call keeps.
  // Given positions that differ, the kept outcome shows that nothing was computed.
  const TriMesh ball = make_sphere_mesh(10, 20);
  Built g({ball}, 4);
  SelfCulling c(g.bvh, g.scene);
  ASSERT_TRUE(c.closed(0));
  const Positions& x0 = ball.vertices;
  Positions pulse(x0.rows()), dent(x0.rows());
  for (std::size_t v = 0; v < x0.rows(); ++v) {
    const Vec3 p = x0.point(v);
    pulse.set_point(v, (1.0 + 0.1 * std::sin(4 * p.x() + 3 * p.z())) * p);
    dent.set_point(v, p.z() > 0.6 ? Vec3(p.x(), p.y(), p.z() - 1.9) : p);
  }
  const SelfCulling::Repeats all = [](std::uint32_t) { return true; }, none = [](std::uint32_t) { return false; };
  auto whole = [&] { return c.covered(0) && c.certified() == 1; };
  c.certify(g.bvh, g.scene.topology(), x0, pulse);
  ASSERT_TRUE(whole());
  c.certify(g.bvh, g.scene.topology(), x0, dent, serial_executor(), {}, nullptr, all);
  EXPECT_TRUE(whole()) << "kept from the last call";
  c.certify(g.bvh, g.scene.topology(), x0, dent, serial_executor(), {}, nullptr, none);
  EXPECT_FALSE(c.covered(0)) << "computed: the dented ball is not star-shaped";
  c.certify(g.bvh, g.scene.topology(), x0, pulse, serial_executor(), {}, nullptr, all);
  EXPECT_FALSE(c.covered(0)) << "the failure kept";
  // a failure holds the next computation off (the back-off): then nothing is known to keep
  c.certify(g.bvh, g.scene.topology(), x0, pulse);
  EXPECT_FALSE(c.covered(0)) << "held off";
  c.certify(g.bvh, g.scene.topology(), x0, pulse, serial_executor(), {}, nullptr, all);
  EXPECT_TRUE(whole()) << "nothing to keep: computed";
  c.certify(g.bvh, g.scene.topology(), x0, dent, serial_executor(), {}, nullptr, all);
  EXPECT_TRUE(whole()) << "kept";
}

TEST(SelfCulling, ALargeClosedSurfaceIsCertifiedTheSameOnAnyNumberOfThreads) {
  // Its centre is summed in blocks (in parallel), the blocks' sums added in order: the same
  // point, so the same certificate and contacts, whatever the threads.
  const TriMesh ball = make_sphere_mesh(48, 96);
  ASSERT_GT(ball.vertices.rows(), 4096u) << "one block only: the test needs a larger surface";
  Positions x1(ball.vertices.rows());
  for (std::size_t v = 0; v < x1.rows(); ++v) {
    const Vec3 p = ball.vertices.point(v);
    x1.set_point(v, Vec3(0.1, 0.2, -0.1) + (1.0 + 0.05 * std::sin(5 * p.y() + 2 * p.x())) * p);
  }
  std::vector<StepResult> results;
  for (int threads : {1, 2, 3, 8}) {
    tbb::task_arena arena(threads);
    arena.execute([&] {
      Scene s({ball});
      results.push_back(s.advance({PositionsView(x1)}));
    });
    EXPECT_EQ(results.back().stats.culled_patches, 1u) << threads << " threads";
    EXPECT_EQ(results.back().stats.leaf_pairs, 0u) << threads << " threads";
    EXPECT_EQ(results.back().contacts, results.front().contacts) << threads << " threads";
  }
}

TEST(SelfCulling, ASurfaceWoundTwiceAroundItsCentreIsNotCertified) {
  // A bipyramid over a 7-gon whose corners wind twice around the z axis: a closed surface of
  // Euler characteristic 2 whose every triangle faces away from the centre through the step,
  // so only the count of the ray (two triangles, not one) keeps it from being certified; its
  // triangles pass through each other.
  const int n = 7;
  TriMesh m;
  m.vertices = Positions(n + 2);
  const auto N = static_cast<std::uint32_t>(n), S = static_cast<std::uint32_t>(n + 1);
  for (int k = 0; k < n; ++k) {
    const double a = 4 * kPi * k / n;
    m.vertices.set_point(k, Vec3(std::cos(a), std::sin(a), 0));
    const auto e = static_cast<std::uint32_t>(k), f = static_cast<std::uint32_t>((k + 1) % n);
    m.faces.push_back({N, e, f});
    m.faces.push_back({S, f, e});
  }
  m.vertices.set_point(N, Vec3(0, 0, 1));
  m.vertices.set_point(S, Vec3(0, 0, -1));
  Positions x1 = m.vertices;
  x1.set_point(N, Vec3(0.3, 0.1, 0.8));
  x1.set_point(S, Vec3(-0.1, -0.3, -0.7));
  for (int k = 0; k < n; ++k) {
    const double a = 4 * kPi * k / n + 0.05 * k;
    x1.set_point(k, Vec3(std::cos(a), std::sin(a), 0.05 * (k % 3)));
  }
  // every triangle keeps one orientation seen from the moving mean of the vertices
  Vec3 c0 = Vec3::Zero(), c1 = Vec3::Zero();
  for (std::size_t v = 0; v < m.vertices.rows(); ++v) c0 += m.vertices.point(v) / (n + 2), c1 += x1.point(v) / (n + 2);
  auto sign = [&](const Triangle& t) {
    return SelfCulling::star_sign(m.vertices.point(t[0]), m.vertices.point(t[1]), m.vertices.point(t[2]), c0,
                                  x1.point(t[0]), x1.point(t[1]), x1.point(t[2]), c1);
  };
  for (const Triangle& t : m.faces) ASSERT_EQ(sign(t), sign(m.faces[0]));
  EXPECT_NE(sign(m.faces[0]), 0);
  Built b({m}, 1);
  EXPECT_EQ(SelfCulling(b.bvh, b.scene).num_closed(), 1u);
  Scene brute({m});
  const StepResult p = brute.step({PositionsView(m.vertices)}, {PositionsView(x1)}, Method::BruteForce);
  EXPECT_GT(p.contacts.size(), 0u);
  SceneOptions o;
  o.leaf_size = 1;
  Scene s({m}, o);
  const StepResult r = s.advance({PositionsView(x1)});
  EXPECT_GT(r.stats.leaf_pairs, 0u);  // the root is not certified
  EXPECT_EQ(r.contacts, p.contacts);
  closed_step(m, x1);
}

TEST(SelfCulling, ClosedBodiesInOneMeshAreEachCertifiedWhole) {
  // Six balls in one mesh, overlapping, turning and closing in on each other over four steps:
  // each is certified whole every step (each has its own subtree: core/bvh.h, tested in
  // test_bvh.cpp), while the contacts between them equal brute force's.
  const int n = 6;
  TriMesh all;
  std::vector<Positions> frames(5);
  const TriMesh ball = make_sphere_mesh(6, 12, 0.5);
  const auto nv = static_cast<std::uint32_t>(ball.vertices.rows());
  all.vertices = Positions(n * nv);
  for (auto& f : frames) f = Positions(n * nv);
  for (int b = 0; b < n; ++b) {
    for (const Triangle& t : ball.faces) all.faces.push_back({t[0] + b * nv, t[1] + b * nv, t[2] + b * nv});
    for (int f = 0; f < 5; ++f) {
      const double a = 0.3 * f + b, gap = 0.62 - 0.02 * f;
      const Vec3 c(gap * b, 0.45 * (b % 2), 0.3 * (b % 3));
      for (std::uint32_t v = 0; v < nv; ++v) {
        const Vec3 p = ball.vertices.point(v);
        const Vec3 q(std::cos(a) * p.x() - std::sin(a) * p.y(), std::sin(a) * p.x() + std::cos(a) * p.y(), p.z());
        frames[f].set_point(b * nv + v, c + q);
      }
    }
  }
  all.vertices = frames[0];
  Scene fbd({all}), phc({all}), brute({all});
  std::uint64_t contacts = 0;
  for (int f = 1; f < 5; ++f) {
    const StepResult r = fbd.advance({PositionsView(frames[f])});
    const StepResult p = brute.step({PositionsView(frames[f - 1])}, {PositionsView(frames[f])}, Method::BruteForce);
    ASSERT_EQ(r.contacts, p.contacts) << "step " << f;
    ASSERT_EQ(phc.advance({PositionsView(frames[f])}, Method::Phc).contacts, p.contacts) << "step " << f;
    EXPECT_GE(r.stats.culled_patches, std::uint64_t(n)) << "step " << f;
    contacts += p.contacts.size();
  }
  EXPECT_GT(contacts, 0u);
}

TEST(SelfCulling, NotUsedWithAMinimumDistance) {
  const AnimatedScene a = make_scene("spheres", 2, 3);
  SceneOptions o;
  o.min_distance = 1e-3;
  Scene s(a.meshes, o);
  for (std::size_t f = 1; f < a.frames.size(); ++f) {
    const StepResult r = s.advance(views(a.frames[f]));
    EXPECT_EQ(r.stats.culled_patches, 0u);
    EXPECT_EQ(r.stats.culled_nodes, 0u);
  }
}
