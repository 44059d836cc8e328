#include <mccd/core/self_culling.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include <mccd/parallel/volume_update.h>

#include <oneapi/tbb/parallel_invoke.h>

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

/// Per face: whether each of its vertices' faces form one fan and each of its edges has at
/// most two faces, in opposite directions (what every patch of a disk needs).
std::vector<std::uint8_t> regular_faces(const MeshTopology& topo) {
  const auto& faces = topo.faces();
  auto corner = [&](std::uint32_t f, std::uint32_t v) {
    return faces[f][0] == v ? 0u : faces[f][1] == v ? 1u : 2u;
  };
  std::vector<std::uint8_t> edge_ok(topo.num_edges(), 0);
  dynamic_for(topo.num_edges(), 8192, [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) {
      const std::uint32_t n = topo.edge_face_count(e);
      if (n == 1) {
        edge_ok[e] = 1;
      } else if (n == 2) {
        const std::uint32_t f = topo.edge_faces_begin(e)[0], g = topo.edge_faces_begin(e)[1];
        unsigned kf = 0, kg = 0;
        while (topo.face_edges(f)[kf] != e) ++kf;
        while (topo.face_edges(g)[kg] != e) ++kg;
        edge_ok[e] = faces[f][kf] == faces[g][(kg + 1) % 3];  // f has a -> b, g has b -> a
      }
    }
  });
  // The other face across edge e from f, or -1 at a boundary.
  auto across = [&](std::uint32_t e, std::uint32_t f) -> std::int64_t {
    if (topo.edge_face_count(e) != 2) return -1;
    const std::uint32_t* g = topo.edge_faces_begin(e);
    return g[0] == f ? g[1] : g[0];
  };
  std::vector<std::uint8_t> vertex_ok(topo.num_vertices(), 0);
  dynamic_for(topo.num_vertices(), 8192, [&](std::size_t begin, std::size_t end) {
    for (std::uint32_t v = static_cast<std::uint32_t>(begin); v < end; ++v) {
      const std::size_t k = topo.vertex_face_count(v);
      if (k == 0) continue;
      bool ok = true;
      for (const std::uint32_t* f = topo.vertex_faces_begin(v); f != topo.vertex_faces_end(v); ++f)
        for (unsigned c = 0; c < 3; ++c)
          if (faces[*f][c] == v)
            ok = ok && edge_ok[topo.face_edges(*f)[c]] && edge_ok[topo.face_edges(*f)[(c + 2) % 3]];
      if (!ok) continue;
      // Walk around v across the edges at v: first leaving each face by its edge v -> next,
      // then, at a boundary, the other way; one fan when the walk meets every face.
      const std::uint32_t f0 = *topo.vertex_faces_begin(v);
      std::size_t seen = 1;
      bool closed = false;
      for (std::uint32_t f = f0; seen <= k;) {
        const std::int64_t g = across(topo.face_edges(f)[corner(f, v)], f);
        if (g < 0) break;
        if (g == f0) {
          closed = true;
          break;
        }
        f = static_cast<std::uint32_t>(g);
        ++seen;
      }
      if (!closed)
        for (std::uint32_t f = f0; seen <= k;) {
          const std::int64_t g = across(topo.face_edges(f)[(corner(f, v) + 2) % 3], f);
          if (g < 0 || g == f0) break;
          f = static_cast<std::uint32_t>(g);
          ++seen;
        }
      vertex_ok[v] = seen == k;
    }
  });
  std::vector<std::uint8_t> ok(topo.num_faces(), 0);
  dynamic_for(topo.num_faces(), 8192, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      bool r = true;
      for (unsigned c = 0; c < 3; ++c) r = r && vertex_ok[faces[f][c]] && edge_ok[topo.face_edges(f)[c]];
      ok[f] = r;
    }
  });
  return ok;
}

using DirectedEdge = std::pair<std::uint32_t, std::uint32_t>;
std::uint64_t key(std::uint32_t a, std::uint32_t b) { return std::uint64_t(a) << 32 | b; }

/// The single simple cycle the directed edges form (each vertex leaves by at most one), or
/// an empty vector.
std::vector<std::uint32_t> one_cycle(const std::vector<DirectedEdge>& edges) {
  if (edges.size() < 3) return {};
  thread_local std::vector<DirectedEdge> next;  // (from, to), sorted
  next.assign(edges.begin(), edges.end());
  std::sort(next.begin(), next.end());
  for (std::size_t i = 1; i < next.size(); ++i)
    if (next[i].first == next[i - 1].first) return {};  // a vertex left twice
  std::vector<std::uint32_t> cycle;
  cycle.reserve(edges.size());
  cycle.push_back(edges[0].first);
  for (std::uint32_t v = edges[0].first;;) {
    const auto it = std::lower_bound(next.begin(), next.end(), DirectedEdge{v, 0});
    if (it == next.end() || it->first != v) return {};
    v = it->second;
    if (v == edges[0].first) break;
    if (cycle.size() == edges.size()) return {};
    cycle.push_back(v);
  }
  if (cycle.size() != edges.size()) return {};
  return cycle;
}

/// Each face's connected component of its mesh (faces joined across shared edges).
std::vector<std::uint32_t> face_components(const MeshTopology& topo) {
  std::vector<std::uint32_t> parent(topo.num_faces());
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t e = 0; e < topo.num_edges(); ++e)
    for (const std::uint32_t* f = topo.edge_faces_begin(e) + 1; f < topo.edge_faces_end(e); ++f)
      parent[root(*f)] = root(topo.edge_faces_begin(e)[0]);
  for (std::uint32_t f = 0; f < parent.size(); ++f) parent[f] = root(f);
  return parent;
}

/// What the disk test needs of a node's triangles, all in one component of their mesh and
/// regular (regular_faces): the directed edges of their boundary (each edge of one of their
/// faces whose other face is not theirs) and their Euler characteristic V - E + F.
/// Triangles of one mesh component share a vertex or an edge only on both boundaries.
/// A patch whose boundary is one simple cycle is connected (each of its components is a
/// proper part of the mesh component, or a whole one without boundary, so each has a boundary
/// of its own), and with characteristic 1 it is a disk.
struct Patch {
  std::vector<DirectedEdge> boundary;
  std::int64_t chi = 0;
  std::uint32_t component = 0;
  bool valid = false;
};

Patch leaf_patch(const std::vector<Triangle>& faces, const std::uint32_t* ids, std::uint32_t n) {
  Patch p;
  // Each edge once per face as (min, max, direction): an edge of two of the leaf's faces
  // appears twice side by side once sorted (the faces are regular: opposite directions).
  constexpr unsigned kMax = 3 * BvhTopology::kMaxLeaf;
  std::uint64_t edges[kMax];
  std::uint32_t vertices[kMax];
  for (std::uint32_t i = 0; i < n; ++i) {
    const Triangle& t = faces[ids[i]];
    for (unsigned c = 0; c < 3; ++c) {
      const std::uint32_t a = t[c], b = t[(c + 1) % 3];
      edges[3 * i + c] = (a < b ? key(a, b) : key(b, a)) << 1 | (a < b ? 0u : 1u);
      vertices[3 * i + c] = a;
    }
  }
  const std::size_t m = 3 * n;
  std::sort(edges, edges + m);
  p.boundary.reserve(m);
  std::size_t unique_edges = 0;
  for (std::size_t i = 0; i < m;) {
    ++unique_edges;
    if (i + 1 < m && edges[i + 1] >> 1 == edges[i] >> 1) {
      i += 2;  // shared by two of the leaf's faces
      continue;
    }
    const std::uint32_t lo = static_cast<std::uint32_t>(edges[i] >> 33), hi = static_cast<std::uint32_t>(edges[i] >> 1);
    if (edges[i] & 1u)
      p.boundary.emplace_back(hi, lo);
    else
      p.boundary.emplace_back(lo, hi);
    ++i;
  }
  std::sort(vertices, vertices + m);
  const std::size_t nv = static_cast<std::size_t>(std::unique(vertices, vertices + m) - vertices);
  p.chi = static_cast<std::int64_t>(nv + n) - static_cast<std::int64_t>(unique_edges);
  p.valid = true;
  return p;
}

/// The union of two patches of one mesh component: shared edges leave the boundary, and the
/// characteristic is the sum less that of the shared part (its vertices less its edges).
Patch union_patch(const Patch& l, const Patch& r) {
  Patch u;
  auto sorted = [](std::vector<std::uint64_t>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  };
  auto has = [](const std::vector<std::uint64_t>& v, std::uint64_t k) {
    return std::binary_search(v.begin(), v.end(), k);
  };
  thread_local std::vector<std::uint64_t> re, rv, lv, cancelled;  // scratch kept from call to call
  re.clear();
  rv.clear();
  lv.clear();
  cancelled.clear();
  u.boundary.reserve(l.boundary.size() + r.boundary.size());
  for (const auto& [a, b] : r.boundary) {
    re.push_back(key(a, b));
    rv.push_back(a);
  }
  sorted(re);
  for (const auto& [a, b] : l.boundary) {
    lv.push_back(a);
    if (has(re, key(a, b))) return u;  // one edge in the same direction: not oriented alike
    if (has(re, key(b, a)))
      cancelled.push_back(key(b, a));
    else
      u.boundary.emplace_back(a, b);
  }
  sorted(cancelled);
  for (const auto& [a, b] : r.boundary)
    if (!has(cancelled, key(a, b))) u.boundary.emplace_back(a, b);
  // Every vertex of a boundary starts one of its edges.
  sorted(lv);
  sorted(rv);
  std::size_t shared_v = 0;
  for (std::size_t i = 0, j = 0; i < lv.size() && j < rv.size();) {
    if (lv[i] < rv[j]) {
      ++i;
    } else if (rv[j] < lv[i]) {
      ++j;
    } else {
      ++shared_v;
      ++i;
      ++j;
    }
  }
  u.chi = l.chi + r.chi - (static_cast<std::int64_t>(shared_v) - static_cast<std::int64_t>(cancelled.size()));
  u.component = l.component;
  u.valid = true;
  return u;
}

}  // namespace

SelfCulling::SelfCulling(const BvhTopology& bvh, const SceneTopology& scene) {
  const MeshTopology& topo = scene.topology();
  const std::uint32_t n = static_cast<std::uint32_t>(bvh.size());
  const std::vector<std::uint8_t> regular = regular_faces(topo);
  const std::vector<std::uint32_t> component = face_components(topo);
  std::vector<std::uint32_t> triangles_below(n, 0);  // filled bottom-up with the patches
  auto triangles = [&](std::uint32_t i) {
    return bvh.leaf(i) ? bvh.leaf_count(i) : triangles_below[bvh.left(i)] + triangles_below[bvh.right(i)];
  };
  std::vector<Patch> patches(n);
  std::vector<std::vector<std::uint32_t>> cycles(n);
  // Bottom-up; subtrees of the top in parallel (each node writes only its own entries).
  auto node = [&](std::uint32_t i) {
    triangles_below[i] = triangles(i);
    const std::uint32_t m = bvh.mesh_of_node(i);
    if (m == BvhTopology::kMixed || scene.skips(m, m)) return;
    Patch& p = patches[i];
    if (bvh.leaf(i)) {
      const std::uint32_t* ids = bvh.leaf_triangles(i);
      bool ok = true;
      for (std::uint32_t k = 0; k < bvh.leaf_count(i); ++k)
        ok = ok && regular[ids[k]] && component[ids[k]] == component[ids[0]];
      if (ok) {
        p = leaf_patch(topo.faces(), ids, bvh.leaf_count(i));
        p.component = component[ids[0]];
      }
    } else {
      Patch& l = patches[bvh.left(i)];
      Patch& r = patches[bvh.right(i)];
      if (l.valid && r.valid && l.component == r.component) p = union_patch(l, r);
      l = Patch();  // the children's boundaries are no longer needed
      r = Patch();
    }
    // A patch whose boundary is long for its size (a disk-like one of F triangles has about
    // 3 sqrt(F) boundary edges, a ragged one, like the leaves of a crumpled cloth, nearly F)
    // rarely becomes a disk higher up and costs most to follow: it is not followed further.
    if (p.valid && double(p.boundary.size()) > 3.5 * std::sqrt(double(triangles(i))) + 8) p = Patch();
    if (p.valid && p.chi == 1) cycles[i] = one_cycle(p.boundary);
  };
  auto subtree = [&](auto&& self, std::uint32_t i) -> void {
    if (bvh.subtree_size(i) < 1024) {
      for (std::uint32_t k = i + bvh.subtree_size(i); k-- > i;) node(k);
      return;
    }
    tbb::parallel_invoke([&] { self(self, bvh.left(i)); }, [&] { self(self, bvh.right(i)); });
    node(i);
  };
  if (n) subtree(subtree, 0);
  cycle_offset_.assign(n + 1, 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    cycle_offset_[i + 1] = cycle_offset_[i] + static_cast<std::uint32_t>(cycles[i].size());
    disks_ += !cycles[i].empty();
  }
  cycle_.reserve(cycle_offset_[n]);
  for (auto& c : cycles) cycle_.insert(cycle_.end(), c.begin(), c.end());
  // The leaves whose signs a step needs: those under an inner disk node (a disk may have
  // children that are not, like ragged leaves). A disk leaf under no inner disk would be tested
  // alone, which costs about what it could save (its own pairs): it is not; nor is a leaf
  // that no disk contains. A disk leaf that is the whole tree is.
  signed_.assign(n, 0);
  for (std::uint32_t i = 0; i < n; ++i)
    if (!bvh.leaf(i))
      for (std::uint32_t c : {bvh.left(i), bvh.right(i)}) signed_[c] = signed_[i] || disk(i);
  if (n == 1) signed_[0] = disk(0);
  signs_.assign(n, 0);
  top_.assign(n, kNone);
}

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

void SelfCulling::certify(const BvhTopology& bvh, const MeshTopology& topo, const Positions& x0, const Positions& x1) {
  const std::uint32_t n = static_cast<std::uint32_t>(bvh.size());
  const auto& faces = topo.faces();
  // The signs each needed leaf's faces share, in parallel over the nodes (a leaf writes its
  // own); then every inner node's, the signs both children share.
  dynamic_for(n, 1024, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i != e; ++i) {
      const std::uint32_t node = static_cast<std::uint32_t>(i);
      if (!bvh.leaf(node) || !signed_[node]) continue;
      unsigned s = 0x3F;
      const std::uint32_t* ids = bvh.leaf_triangles(node);
      for (std::uint32_t k = 0; k < bvh.leaf_count(node) && s; ++k) {
        const Triangle& t = faces[ids[k]];
        s = normal_signs(x0.point(t[0]), x0.point(t[1]), x0.point(t[2]), x1.point(t[0]), x1.point(t[1]),
                         x1.point(t[2]), s);
      }
      signs_[node] = static_cast<std::uint8_t>(s);
    }
  });
  for (std::uint32_t i = n; i-- > 0;)
    if (!bvh.leaf(i)) signs_[i] = signs_[bvh.left(i)] & signs_[bvh.right(i)];
  // Top-down: the first node on each path whose faces share a sign along an axis and whose
  // contour passes along that axis covers its subtree. The subtrees of the tree's top in
  // parallel: each writes only its own nodes, and the counts add up the same either way.
  auto certifies = [&](std::uint32_t i) {
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
    if (bvh.subtree_size(i) <= 1024) return serial(i, i + bvh.subtree_size(i));
    if (certifies(i)) {
      std::fill(top_.begin() + i, top_.begin() + i + bvh.subtree_size(i), i);
      return 1;
    }
    top_[i] = kNone;
    std::uint64_t l = 0, r = 0;
    tbb::parallel_invoke([&] { l = self(self, bvh.left(i)); }, [&] { r = self(self, bvh.right(i)); });
    return l + r;
  };
  certified_ = n ? subtree(subtree, 0) : 0;
  active_ = true;
}

}  // namespace mccd::detail
