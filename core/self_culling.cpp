/// @file The per-step half of self-collision culling (core/self_culling.h): the normal signs
/// and contour tests and the top-down certification; the disks are found in
/// self_culling_disks.cpp.
#include <mccd/core/self_culling.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

#include <mccd/geometry/assert.h>

namespace mccd::detail {

namespace {

/// A sum of at most four products of differences of doubles is within 6u (u = 2^-53) of the
/// sum of the products' magnitudes of its exact value (one rounding per difference, per
/// product and per addition); 16u leaves room for the rounding of the bound itself.
constexpr double kBound = 0x1p-49;
/// Below this sum of magnitudes a product may have lost bits to underflow: no sign is certain.
constexpr double kTiny = 0x1p-900;

/// The sign a quadratic in Bernstein form keeps on [0, 1], when its three coefficients share
/// one with certainty: +1, -1, or 0 (not certain). `v`: computed coefficients; `e`: the sums of
/// the magnitudes of their products.
[[gnu::always_inline]] inline int bernstein_sign(const std::array<double, 3>& v, const std::array<double, 3>& e) {
  // (every comparison made, no branch: the signs mispredict)
  const int pos = int(v[0] > kBound * e[0]) & int(v[1] > kBound * e[1]) & int(v[2] > kBound * e[2]);
  const int neg = int(v[0] < -kBound * e[0]) & int(v[1] < -kBound * e[1]) & int(v[2] < -kBound * e[2]);
  const int normal = int(e[0] > kTiny) & int(e[1] > kTiny) & int(e[2] > kTiny);
  return normal ? pos - neg : 0;
}

using P2 = std::array<double, 2>;

/// The Bernstein coefficients (and their error scales) of dot(A(t), B(t)) (`cross` false) or
/// cross(A(t), B(t)), with A and B linear in t from A0, B0 to A1, B1 (the middle coefficient
/// doubled, which keeps its sign).
template <bool cross>
[[gnu::always_inline]] inline int product_sign(const P2& a0, const P2& b0, const P2& a1, const P2& b1) {
  auto term = [&](const P2& a, const P2& b, double& mag) {
    const double p = a[0] * (cross ? b[1] : b[0]);
    const double q = a[1] * (cross ? b[0] : b[1]);
    mag += std::abs(p) + std::abs(q);
    return cross ? p - q : p + q;
  };
  std::array<double, 3> v{}, e{};
  v[0] = term(a0, b0, e[0]);
  v[1] = term(a0, b1, e[1]) + term(a1, b0, e[1]);
  v[2] = term(a1, b1, e[2]);
  return bernstein_sign(v, e);
}

}  // namespace

unsigned SelfCulling::normal_signs(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a1, const Vec3& b1,
                                   const Vec3& c1, unsigned wanted) {
  const Vec3 u0 = b0 - a0, v0 = c0 - a0, u1 = b1 - a1, v1 = c1 - a1;
  unsigned bits = 0;
  for (int d = 0; d < 3; ++d) {
    if (!(wanted >> (2 * d) & 3u)) continue;
    const int i = (d + 1) % 3, j = (d + 2) % 3;
    // The d component of the normal (b - a) x (c - a), a quadratic in t: its Bernstein
    // coefficients from the ends' products (the middle one doubled).
    const P2 p0{u0[i], u0[j]}, q0{v0[i], v0[j]}, p1{u1[i], u1[j]}, q1{v1[i], v1[j]};
    const int s = product_sign<true>(p0, q0, p1, q1);
    bits |= s > 0 ? 1u << (2 * d) : s < 0 ? 2u << (2 * d) : 0u;
  }
  return bits & wanted;
}

namespace {

double max_norm(const Vec3& v) { return std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])}); }

/// A sum of at most 18 products of three differences of doubles, each factor at most U, V, W
/// in magnitude, computed with each difference, product and sum rounded once (in any order):
/// within about 12u * 18 U V W of its exact value. kBound3 = 128u leaves room for the
/// rounding of the bound itself.
constexpr double kBound3 = 0x1p-46;

/// The sign of `v` when its exact counterpart is within kBound3 * `scale` of it: +1, -1, or 0
/// (not certain, or a scale small enough that products may have lost bits to underflow).
[[gnu::always_inline]] inline int certain_sign(double v, double scale) {
  if (!(scale > kTiny)) return 0;
  return v > kBound3 * scale ? 1 : v < -kBound3 * scale ? -1 : 0;
}

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// The sign `s` (2: none yet, 0: failed, else +1 or -1) shares with signs[0, n) (each +1, -1
/// or 0): the common one, or 0 where they differ or one is 0. Without an early exit, so that
/// the loop runs in vector lanes.
int fold_signs(int s, const std::int8_t* signs, std::size_t n) {
  if (s == 0 || n == 0) return s;
  bool all_pos = true, all_neg = true;
  for (std::size_t q = 0; q < n; ++q) {
    all_pos &= signs[q] == 1;
    all_neg &= signs[q] == -1;
  }
  const int batch = all_pos ? 1 : all_neg ? -1 : 0;
  return s == 2 || s == batch ? batch : 0;
}

}  // namespace

int SelfCulling::star_sign(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& p0, const Vec3& a1,
                           const Vec3& b1, const Vec3& c1, const Vec3& p1) {
  // det(u(t), v(t), w(t)) with u = b - a, v = c - a, w = p - a, each linear in t: a cubic.
  // Its Bernstein coefficients are the trilinear form's values at the ends (the middle two
  // times 3, which keeps their signs): with n0 = u0 x v0, n1 = u1 x v1, nm = u0 x v1 + u1 x v0,
  // D0 = n0.w0, D1 = nm.w0 + n0.w1, D2 = nm.w1 + n1.w0, D3 = n1.w1, each a sum of at most 18
  // products of three differences.
  const Vec3 u0 = b0 - a0, u1 = b1 - a1, v0 = c0 - a0, v1 = c1 - a1, w0 = p0 - a0, w1 = p1 - a1;
  const Vec3 n0 = cross(u0, v0), n1 = cross(u1, v1), nm = cross(u0, v1) + cross(u1, v0);
  const double d[4] = {dot(n0, w0), dot(nm, w0) + dot(n0, w1), dot(nm, w1) + dot(n1, w0), dot(n1, w1)};
  const double scale = 18 * std::max(max_norm(u0), max_norm(u1)) * std::max(max_norm(v0), max_norm(v1)) *
                       std::max(max_norm(w0), max_norm(w1));
  const int s0 = certain_sign(d[0], scale), s1 = certain_sign(d[1], scale), s2 = certain_sign(d[2], scale),
            s3 = certain_sign(d[3], scale);
  if (s0 != 0 && s0 == s1 && s1 == s2 && s2 == s3) return s0;
  // The cubic split at t = 1/2 (de Casteljau): with b = (d0, d1 / 3, d2 / 3, d3) its Bernstein
  // coefficients, each half's inner ones times 6 or 12 are the sums below, of weight 4 or 6
  // (the sum of their factors). A body turning by more than 120 degrees in the step (a rigid
  // turn by angle a scales the cubic by a quadratic whose middle coefficient is cos a) keeps its
  // sign on [0, 1] with middle coefficients of the wrong sign; on the halves they have the
  // right one up to 180 degrees. A sum of weight k is within about k * 12u * scale of its exact
  // value plus its own roundings (a few u * k * scale): certain beyond k * kBound3 * scale.
  if (s0 == 0 || s0 != s3) return 0;
  const double t0 = 3 * d[0], t3 = 3 * d[3], a12 = d[1] + d[2];
  const double l1 = t0 + d[1], l2 = l1 + a12, mid = (d[0] + d[1]) + (d[2] + d[3]), r2 = a12 + (d[2] + t3),
               r1 = d[2] + t3;
  const double halves[5][2] = {{l1, 4}, {l2, 6}, {mid, 4}, {r2, 6}, {r1, 4}};
  for (const auto& [h, weight] : halves)
    if (certain_sign(h, weight * scale) != s0) return 0;
  return s0;
}

unsigned SelfCulling::normal_signs_in_lanes(const LaneKernels& lanes, const double* x0, const double* x1,
                                            const std::uint32_t (*corners)[3], std::size_t n, std::uint8_t* bits) {
  return lanes.normal_signs(x0, x1, corners, n, kBound, kTiny, bits);
}

void SelfCulling::star_signs(const LaneKernels& lanes, const double* x0, const double* x1,
                             const std::uint32_t (*corners)[3], std::size_t n, const double* m0, const double* m1,
                             std::int8_t* signs) {
  lanes.star_signs(x0, x1, corners, n, m0, m1, kBound3, kTiny, signs);
}

bool SelfCulling::certify_closed(std::size_t k, const BvhTopology& bvh, const MeshTopology& topo, const Positions& x0,
                                 const Positions& x1, const Executor& ex, const RayMeets& ray_meets,
                                 const Triangle* leaf_corners) const {
  const std::uint32_t node = closed_[k];
  // c(t): the mean of the component's vertices at each end (any point would do; this one is
  // inside a star-shaped body). Summed in blocks of a fixed size, in parallel for a large
  // surface (a serial pass was most of a large body's certificate on many threads), the
  // blocks' sums added in order: the same mean on any number of threads.
  constexpr std::uint32_t kMeanBlock = 4096;
  const std::uint32_t vb = closed_vertex_begin_[k], ve = closed_vertex_begin_[k + 1];
  auto block_sum = [&](std::uint32_t b, std::uint32_t e, Vec3& s0, Vec3& s1) {
    s0 = Vec3::Zero(), s1 = Vec3::Zero();
    for (std::uint32_t i = b; i != e; ++i) {
      s0 += x0.point(closed_vertices_[i]);
      s1 += x1.point(closed_vertices_[i]);
    }
  };
  Vec3 m0, m1;
  if (ve - vb <= kMeanBlock) {
    block_sum(vb, ve, m0, m1);
  } else {
    const std::uint32_t blocks = (ve - vb + kMeanBlock - 1) / kMeanBlock;
    std::vector<Vec3> sums(2 * std::size_t(blocks));
    ex.dynamic_for(blocks, 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t j = b; j != e; ++j) {
        const std::uint32_t from = vb + static_cast<std::uint32_t>(j) * kMeanBlock;
        block_sum(from, std::min(ve, from + kMeanBlock), sums[2 * j], sums[2 * j + 1]);
      }
    });
    m0 = sums[0], m1 = sums[1];
    for (std::uint32_t j = 1; j < blocks; ++j) m0 += sums[2 * j], m1 += sums[2 * j + 1];
  }
  m0 /= double(ve - vb);
  m1 /= double(ve - vb);
  if (!m0.allFinite() || !m1.allFinite()) return false;
  const auto& faces = topo.faces();
  const std::uint32_t end = node + bvh.subtree_size(node);
  // The ray from c(0) towards a point inside the first triangle, near its centroid but off the
  // planes of symmetry a regular mesh may have (a ray in the plane of c(0) and another
  // triangle's edge could not be counted).
  std::uint32_t first = node;
  while (!bvh.leaf(first)) first = bvh.left(first);
  const Triangle& t0 = faces[bvh.leaf_triangles(first)[0]];
  const Vec3 r = 0.31 * x0.point(t0[0]) + 0.33 * x0.point(t0[1]) + 0.36 * x0.point(t0[2]) - m0;
  const double nr = max_norm(r);
  // Every triangle's orientation seen from c(t), certain and the same: over blocks of the
  // subtree's nodes in parallel (a large surface is most of the step's certification), each
  // block's common sign merged into one (any order gives the same outcome).
  std::atomic<int> common{2};  // 2: none yet; 0: failed
  // The triangles' signs a batch at a time in vector lanes (LaneKernels::star_signs: star_sign's
  // values bit for bit).
  const LaneKernels& lanes = lane_kernels();
  const double c0[3] = {m0[0], m0[1], m0[2]}, c1[3] = {m1[0], m1[1], m1[2]};
  auto merge_sign = [&common](int s) {
    int expected = 2;
    if (!common.compare_exchange_strong(expected, s, std::memory_order_relaxed) && expected != s)
      common.store(0, std::memory_order_relaxed);
  };
  if (leaf_corners) {
    // The subtree's triangles are one range of the leaf order, their corners side by side
    // there: the lanes read them in place, a block at a time.
    std::uint32_t last = node;
    while (!bvh.leaf(last)) last = bvh.right(last);
    const std::uint32_t begin = bvh.leaf_first(first), count = bvh.leaf_first(last) + bvh.leaf_count(last) - begin;
    MCCD_ASSERT(([&] {
                  std::uint32_t sum = 0;
                  for (std::uint32_t i = node; i != end; ++i) sum += bvh.leaf(i) ? bvh.leaf_count(i) : 0;
                  return sum == count;
                }()),
                "a subtree's triangles are one range of the leaf order");
    static_assert(sizeof(Triangle) == 3 * sizeof(std::uint32_t), "a triangle's corners as three ids in a row");
    const auto* corners = reinterpret_cast<const std::uint32_t(*)[3]>(leaf_corners + begin);
    ex.dynamic_for(count, 4096, [&](std::size_t b, std::size_t e) {
      constexpr std::size_t kBatch = 256;
      std::int8_t signs[kBatch];
      int s = 2;
      for (std::size_t at = b; at < e && s != 0; at += kBatch) {
        const std::size_t n = std::min(kBatch, e - at);
        star_signs(lanes, x0.data(), x1.data(), corners + at, n, c0, c1, signs);
        s = fold_signs(s, signs, n);
      }
      if (s != 2) merge_sign(s);
    });
  } else {
    ex.dynamic_for(end - node, 2048, [&](std::size_t b, std::size_t e) {
      constexpr unsigned kBatch = 64;
      std::uint32_t corners[kBatch + BvhTopology::kMaxLeaf][3];
      std::int8_t signs[kBatch + BvhTopology::kMaxLeaf];
      unsigned queued = 0;
      int s = 2;
      auto flush = [&] {
        star_signs(lanes, x0.data(), x1.data(), corners, queued, c0, c1, signs);
        s = fold_signs(s, signs, queued);
        queued = 0;
      };
      for (std::uint32_t i = node + static_cast<std::uint32_t>(b); i != node + e && s != 0; ++i) {
        if (!bvh.leaf(i)) continue;
        const std::uint32_t* ids = bvh.leaf_triangles(i);
        for (std::uint32_t q = 0; q < bvh.leaf_count(i); ++q) {
          const Triangle& t = faces[ids[q]];
          corners[queued][0] = t[0], corners[queued][1] = t[1], corners[queued][2] = t[2];
          ++queued;
        }
        if (queued >= kBatch) flush();
      }
      if (queued && s != 0) flush();
      if (s != 2) merge_sign(s);  // (2: no leaf in this block)
    });
  }
  const int s = common.load(std::memory_order_relaxed);
  if (s != 1 && s != -1) return false;
  // The triangles whose cones hold the ray, among those of the nodes whose volumes may meet it
  // at the start (the others' triangles certainly do not).
  unsigned hits = 0;
  for (std::uint32_t i = node; i != end;) {
    if (ray_meets && !ray_meets(i, m0, r)) {
      i += bvh.subtree_size(i);
      continue;
    }
    if (!bvh.leaf(i)) {
      ++i;
      continue;
    }
    const std::uint32_t* ids = bvh.leaf_triangles(i);
    for (std::uint32_t q = 0; q < bvh.leaf_count(i); ++q) {
      // Seen from c(0) the triangle spans the cone of a, b, c, oriented by -s; the ray is
      // inside it when r = alpha a + beta b + gamma c with all three positive (Cramer's rule).
      const Triangle& t = faces[ids[q]];
      const Vec3 a = x0.point(t[0]) - m0, b = x0.point(t[1]) - m0, c = x0.point(t[2]) - m0;
      const double na = max_norm(a), nb = max_norm(b), nc = max_norm(c);
      const int sa = certain_sign(dot(r, cross(b, c)), 6 * nr * nb * nc),
                sb = certain_sign(dot(a, cross(r, c)), 6 * na * nr * nc),
                sc = certain_sign(dot(a, cross(b, r)), 6 * na * nb * nr);
      const int inside = (sa == -s) + (sb == -s) + (sc == -s), outside = (sa == s) + (sb == s) + (sc == s);
      if (inside == 3)
        ++hits;
      else if (outside == 0)
        return false;  // too close to the cone's boundary to tell
    }
    ++i;
  }
  return hits == 1;
}

bool SelfCulling::contour_simple(const std::uint32_t* begin, const std::uint32_t* end, unsigned axis,
                                 const Positions& x0, const Positions& x1) {
  const std::size_t n = static_cast<std::size_t>(end - begin);
  if (n < 3) return false;
  const int i = static_cast<int>(axis + 1) % 3, j = static_cast<int>(axis + 2) % 3;
  // scratch kept by each thread from call to call
  thread_local std::vector<P2> p0, p1;
  p0.resize(n);
  p1.resize(n);
  P2 c0{0, 0}, c1{0, 0};
  for (std::size_t k = 0; k < n; ++k) {
    p0[k] = {x0(begin[k], i), x0(begin[k], j)};
    p1[k] = {x1(begin[k], i), x1(begin[k], j)};
    for (int a = 0; a < 2; ++a) {
      c0[a] += p0[k][a];
      c1[a] += p1[k][a];
    }
  }
  // Consecutive edges meet only at their common vertex: at every time the two directions
  // from it are not the same (their dot product stays negative, or their cross product keeps
  // one sign). Each edge has a face of the patch, which keeps a strict orientation, so no
  // edge shrinks to a point.
  auto minus = [](const P2& a, const P2& b) { return P2{a[0] - b[0], a[1] - b[1]}; };
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t prev = k == 0 ? n - 1 : k - 1, next = k + 1 == n ? 0 : k + 1;
    const P2 a0 = minus(p0[prev], p0[k]), b0 = minus(p0[next], p0[k]);
    const P2 a1 = minus(p1[prev], p1[k]), b1 = minus(p1[next], p1[k]);
    if (product_sign<false>(a0, b0, a1, b1) < 0) continue;
    if (product_sign<true>(a0, b0, a1, b1) != 0) continue;
    return false;
  }
  // Other edges never meet: their boxes over the step are apart. A common translation moving
  // linearly (the cycle's mean) changes no meeting and is taken out first; the rounding of
  // that subtraction (at most u of each result) is covered by widening every box by 8u of the
  // largest coordinate.
  for (int a = 0; a < 2; ++a) {
    c0[a] /= static_cast<double>(n);
    c1[a] /= static_cast<double>(n);
  }
  double extent = 0;
  for (std::size_t k = 0; k < n; ++k)
    for (int a = 0; a < 2; ++a) {
      p0[k][a] -= c0[a];
      p1[k][a] -= c1[a];
      extent = std::max({extent, std::abs(p0[k][a]), std::abs(p1[k][a])});
    }
  const double eta = extent * 0x1p-50;
  struct Box {
    double lo[2], hi[2];
    std::uint32_t edge;
  };
  thread_local std::vector<Box> boxes;
  boxes.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t next = k + 1 == n ? 0 : k + 1;
    Box& b = boxes[k];
    b.edge = static_cast<std::uint32_t>(k);
    for (int a = 0; a < 2; ++a) {
      b.lo[a] = std::min({p0[k][a], p1[k][a], p0[next][a], p1[next][a]}) - eta;
      b.hi[a] = std::max({p0[k][a], p1[k][a], p0[next][a], p1[next][a]}) + eta;
    }
  }
  auto consecutive = [n](std::uint32_t e, std::uint32_t f) {
    const std::uint32_t d = e > f ? e - f : f - e;
    return d <= 1 || d == n - 1;
  };
  // Edges e and f whose boxes meet are still apart when a line separates them at every time:
  // one direction w along which each end of f lies beyond each end of e at both ends of the
  // step (the gaps are linear in t). Tried: the normals of the two edges at both times.
  auto separated = [&](std::uint32_t e, std::uint32_t f) {
    const std::uint32_t e1 = e + 1 == n ? 0 : e + 1, f1 = f + 1 == n ? 0 : f + 1;
    const P2* ends[2][2][2] = {{{&p0[e], &p0[e1]}, {&p1[e], &p1[e1]}}, {{&p0[f], &p0[f1]}, {&p1[f], &p1[f1]}}};
    for (int side = 0; side < 2; ++side)
      for (int t = 0; t < 2; ++t) {
        const P2& a = *ends[side][t][0];
        const P2& b = *ends[side][t][1];
        const P2 w{a[1] - b[1], b[0] - a[0]};
        const double wsum = std::abs(w[0]) + std::abs(w[1]);
        int sign = 0;
        bool ok = true;
        for (int tt = 0; tt < 2 && ok; ++tt)
          for (int i = 0; i < 2 && ok; ++i)
            for (int k = 0; k < 2 && ok; ++k) {
              const P2& p = *ends[0][tt][i];
              const P2& q = *ends[1][tt][k];
              const double dx = q[0] - p[0], dy = q[1] - p[1];
              const double v = w[0] * dx + w[1] * dy;
              // The coordinates are within eta of the exact ones, each difference and the
              // dot product add their roundings.
              const double err = wsum * (2 * eta + kBound * (std::abs(dx) + std::abs(dy))) +
                                 kBound * (std::abs(w[0] * dx) + std::abs(w[1] * dy));
              const int s = v > err ? 1 : v < -err ? -1 : 0;
              ok = s != 0 && (sign == 0 || s == sign);
              sign = s;
            }
        if (ok) return true;
      }
    return false;
  };
  // Sweep along the first coordinate: each box against those still open.
  std::sort(boxes.begin(), boxes.end(), [](const Box& x, const Box& y) { return x.lo[0] < y.lo[0]; });
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t m = k + 1; m < n && boxes[m].lo[0] <= boxes[k].hi[0]; ++m)
      if (boxes[m].lo[1] <= boxes[k].hi[1] && boxes[k].lo[1] <= boxes[m].hi[1] &&
          !consecutive(boxes[k].edge, boxes[m].edge) && !separated(boxes[k].edge, boxes[m].edge))
        return false;
  return true;
}

void SelfCulling::certify(const BvhTopology& bvh, const MeshTopology& topo, const Positions& x0, const Positions& x1,
                          const Executor& ex, const RayMeets& ray_meets, const Triangle* leaf_corners,
                          const Repeats& repeats) {
  const LaneKernels& lanes = lane_kernels();
  const std::uint32_t n = static_cast<std::uint32_t>(bvh.size());
  const auto& faces = topo.faces();
  // Closed surfaces (each certified whole covers every node below it), in parallel, beside
  // the signs of the leaves under no closed surface; then the leaves under a closed surface
  // not certified this step. The leaves under a certified one need none (never read).
  auto certify_closed_all = [&] {
    ex.dynamic_for(closed_.size(), 1, [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k != e; ++k) {
        // A surface whose step repeats the last call's keeps that call's outcome (the
        // certificate is a function of its corners' positions and its nodes' volumes).
        if (closed_last_[k] != kUnknown && repeats && repeats(closed_[k])) {
          closed_ok_[k] = closed_last_[k];
          continue;
        }
        // After f failures in a row the next 2^f - 1 steps (at most 63) are not tried: a closed
        // surface that is not star-shaped from its mean costs a pass over its triangles for
        // nothing. A success starts over.
        Backoff& o = closed_backoff_[k];
        closed_ok_[k] = 0;
        closed_last_[k] = kUnknown;
        if (o.skip) {
          --o.skip;
          continue;
        }
        closed_ok_[k] = certify_closed(k, bvh, topo, x0, x1, ex, ray_meets, leaf_corners);
        closed_last_[k] = closed_ok_[k];
        o.failures = closed_ok_[k] ? 0 : std::min(o.failures + 1, 6);
        o.skip = (1 << o.failures) - 1;
      }
    });
  };
  // The signs each needed leaf's faces share (a leaf writes its own).
  auto leaf_signs = [&](std::uint32_t node) {
    // The leaf's triangles in vector lanes (LaneKernels::normal_signs: normal_signs' values
    // bit for bit), every axis: the signs they all share are the same as axis by axis.
    const std::uint32_t count = bvh.leaf_count(node);
    std::uint32_t copied[BvhTopology::kMaxLeaf][3];
    const std::uint32_t(*corners)[3] = copied;
    if (leaf_corners) {  // read in place (certify_closed's layout)
      corners = reinterpret_cast<const std::uint32_t(*)[3]>(leaf_corners + bvh.leaf_first(node));
    } else {
      const std::uint32_t* ids = bvh.leaf_triangles(node);
      for (std::uint32_t k = 0; k < count; ++k) {
        const Triangle& t = faces[ids[k]];
        copied[k][0] = t[0], copied[k][1] = t[1], copied[k][2] = t[2];
      }
    }
    const unsigned shared = normal_signs_in_lanes(lanes, x0.data(), x1.data(), corners, count, nullptr);
    signs_[node] = static_cast<std::uint8_t>(shared);
  };
  // The needed leaves' signs: of the leaves under a closed surface (`under_closed`; under one
  // certified this step none is needed) or of those under none.
  auto signs_of_leaves = [&](bool under_closed) {
    ex.dynamic_for(n, 64, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i != e; ++i) {
        const std::uint32_t node = static_cast<std::uint32_t>(i);
        if (!bvh.leaf(node) || !signed_[node] || (closed_above_[node] != kNone) != under_closed) continue;
        if (under_closed && closed_ok_[closed_above_[node]]) {
          signs_[node] = 0;  // covered whole; never read this step
          continue;
        }
        leaf_signs(node);
      }
    });
  };
  if (closed_.empty()) {
    signs_of_leaves(false);
  } else {
    ex.invoke(certify_closed_all, [&] { signs_of_leaves(false); });
    signs_of_leaves(true);
  }
  // Every inner node's signs, those both children share: the tree's subtrees bottom-up in
  // parallel (a subtree's nodes lie together, each child after its parent), then the nodes
  // above them, deepest first. The cut is made once: the tree never changes shape.
  if (sign_cut_nodes_ != n) {
    sign_roots_.clear();
    sign_top_.clear();
    sign_cut_nodes_ = n;
    const std::uint32_t limit = std::max<std::uint32_t>(256, n / 64);
    std::vector<std::uint32_t> stack;
    if (n != 0) stack.push_back(0);
    while (!stack.empty()) {
      const std::uint32_t i = stack.back();
      stack.pop_back();
      if (bvh.leaf(i) || bvh.subtree_size(i) <= limit) {
        sign_roots_.push_back(i);
      } else {
        sign_top_.push_back(i);
        stack.push_back(bvh.left(i));
        stack.push_back(bvh.right(i));
      }
    }
    std::sort(sign_top_.begin(), sign_top_.end(), std::greater<>());  // children (larger ids) first
  }
  ex.dynamic_for(sign_roots_.size(), 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k != e; ++k) {
      const std::uint32_t r = sign_roots_[k];
      for (std::uint32_t i = r + bvh.subtree_size(r); i-- > r;)
        if (!bvh.leaf(i)) signs_[i] = signs_[bvh.left(i)] & signs_[bvh.right(i)];
    }
  });
  for (std::uint32_t i : sign_top_) signs_[i] = signs_[bvh.left(i)] & signs_[bvh.right(i)];
  // Top-down: the first node on each path whose faces share a sign along an axis and whose
  // contour passes along that axis covers its subtree. The subtrees of the tree's top in
  // parallel: each writes only its own nodes, and the counts add up the same either way.
  auto certifies = [&](std::uint32_t i) {
    if (closed_above_[i] != kNone && closed_[closed_above_[i]] == i && closed_ok_[closed_above_[i]]) return true;
    if (!disk(i)) return false;
    for (unsigned d = 0; d < 3; ++d)
      if ((signs_[i] >> (2 * d) & 3u) && contour_simple(cycle_begin(i), cycle_end(i), d, x0, x1)) return true;
    return false;
  };
  auto serial = [&](std::uint32_t begin, std::uint32_t end) {
    std::uint64_t count = 0;
    for (std::uint32_t i = begin; i < end;) {
      if (!certifies(i)) {
        top_[i++] = kNone;
        continue;
      }
      const std::uint32_t below = i + bvh.subtree_size(i);
      std::fill(top_.begin() + i, top_.begin() + below, i);
      ++count;
      i = below;
    }
    return count;
  };
  auto subtree = [&](auto&& self, std::uint32_t i) -> std::uint64_t {
    if (bvh.subtree_size(i) <= 64) return serial(i, i + bvh.subtree_size(i));
    if (certifies(i)) {
      std::fill(top_.begin() + i, top_.begin() + i + bvh.subtree_size(i), i);
      return 1;
    }
    top_[i] = kNone;
    std::uint64_t l = 0, r = 0;
    ex.invoke([&] { l = self(self, bvh.left(i)); }, [&] { r = self(self, bvh.right(i)); });
    return l + r;
  };
  certified_ = n ? subtree(subtree, 0) : 0;
  active_ = true;
}

}  // namespace mccd::detail
