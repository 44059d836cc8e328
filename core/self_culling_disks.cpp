/// @file The once-per-scene half of self-collision culling (core/self_culling.h): which BVH
/// nodes' triangles form topological disks, and their boundary cycles. Depends only on the
/// meshes' connectivity and the tree; the per-step certification is in self_culling.cpp.
#include <mccd/core/self_culling.h>

#include <algorithm>
#include <cmath>

#include <mccd/geometry/disjoint_sets.h>
#include <mccd/geometry/large_allocator.h>

namespace mccd::detail {

namespace {

/// Per face: whether each of its vertices' faces form one fan and each of its edges has at
/// most two faces, in opposite directions (what every patch of a disk needs).
std::vector<std::uint8_t> regular_faces(const MeshTopology& topo, const Executor& ex) {
  const auto& faces = topo.faces();
  auto corner = [&](std::uint32_t f, std::uint32_t v) {
    return faces[f][0] == v ? 0u : faces[f][1] == v ? 1u : 2u;
  };
  std::vector<std::uint8_t> edge_ok(topo.num_edges(), 0);
  ex.dynamic_for(topo.num_edges(), 8192, [&](std::size_t begin, std::size_t end) {
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
  ex.dynamic_for(topo.num_vertices(), 8192, [&](std::size_t begin, std::size_t end) {
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
  ex.dynamic_for(topo.num_faces(), 8192, [&](std::size_t begin, std::size_t end) {
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
  DisjointSets sets(topo.num_faces());
  for (std::size_t e = 0; e < topo.num_edges(); ++e)
    for (const std::uint32_t* f = topo.edge_faces_begin(e) + 1; f < topo.edge_faces_end(e); ++f)
      sets.unite(*f, topo.edge_faces_begin(e)[0]);
  return std::move(sets).roots();
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

SelfCulling::SelfCulling(const BvhTopology& bvh, const SceneTopology& scene, const Executor& ex) {
  const MeshTopology& topo = scene.topology();
  const std::uint32_t n = static_cast<std::uint32_t>(bvh.size());
  // The faces' regularity (parallel itself) beside their components (serial).
  std::vector<std::uint8_t> regular;
  std::vector<std::uint32_t> component;
  ex.invoke([&] { regular = regular_faces(topo, ex); }, [&] { component = face_components(topo); });
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
    ex.invoke([&] { self(self, bvh.left(i)); }, [&] { self(self, bvh.right(i)); });
    node(i);
  };
  // The disks beside the closed components (find_closed: serial; it writes only the closed_
  // members, the disks only the others).
  ex.invoke([&] { if (n) subtree(subtree, 0); }, [&] { find_closed(bvh, scene, regular, component); });
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

void SelfCulling::find_closed(const BvhTopology& bvh, const SceneTopology& scene, const std::vector<std::uint8_t>& regular,
                              const std::vector<std::uint32_t>& component) {
  const MeshTopology& topo = scene.topology();
  const std::uint32_t n = static_cast<std::uint32_t>(bvh.size());
  // Per component: its faces, and whether it is closed and regular (each edge with exactly two
  // faces, each face regular) with V - E + F = 2.
  const std::size_t nf = topo.num_faces();
  // Arrays per component, indexed by a face id: each backed in one call (backed_assign)
  // rather than faulted in page by page.
  std::vector<std::uint32_t> faces_of;
  backed_assign(faces_of, nf);
  std::vector<std::uint8_t> sphere;
  backed_assign(sphere, nf, std::uint8_t(1));
  for (std::size_t f = 0; f < nf; ++f) {
    ++faces_of[component[f]];
    if (!regular[f]) sphere[component[f]] = 0;
  }
  std::vector<std::int64_t> chi;
  backed_assign(chi, nf);
  for (std::size_t f = 0; f < nf; ++f) chi[component[f]] += 1;
  for (std::size_t e = 0; e < topo.num_edges(); ++e) {
    const std::uint32_t c = component[topo.edge_faces_begin(e)[0]];
    chi[c] -= 1;
    if (topo.edge_face_count(e) != 2) sphere[c] = 0;
  }
  for (std::size_t v = 0; v < topo.num_vertices(); ++v)
    if (topo.vertex_face_count(v)) chi[component[*topo.vertex_faces_begin(v)]] += 1;
  // Per node, bottom-up: the one component of all its triangles, or kNone; and their number.
  std::vector<std::uint32_t> comp(n, kNone), count(n, 0);
  for (std::uint32_t i = n; i-- > 0;) {
    if (bvh.leaf(i)) {
      const std::uint32_t* ids = bvh.leaf_triangles(i);
      comp[i] = component[ids[0]];
      for (std::uint32_t k = 1; k < bvh.leaf_count(i); ++k)
        if (component[ids[k]] != comp[i]) comp[i] = kNone;
      count[i] = bvh.leaf_count(i);
    } else {
      const std::uint32_t l = bvh.left(i), r = bvh.right(i);
      comp[i] = comp[l] == comp[r] ? comp[l] : kNone;
      count[i] = count[l] + count[r];
    }
  }
  closed_above_.assign(n, kNone);
  closed_vertex_begin_.assign(1, 0);
  for (std::uint32_t i = 0; i < n;) {
    const std::uint32_t m = bvh.mesh_of_node(i), c = comp[i];
    const bool candidate = m != BvhTopology::kMixed && !scene.skips(m, m) && c != kNone && count[i] == faces_of[c] &&
                           sphere[c] && chi[c] == 2 && count[i] >= 4;
    if (!candidate) {
      ++i;
      continue;
    }
    const std::uint32_t end = i + bvh.subtree_size(i);
    std::fill(closed_above_.begin() + i, closed_above_.begin() + end, static_cast<std::uint32_t>(closed_.size()));
    closed_.push_back(i);
    std::vector<std::uint32_t> vs;
    for (std::uint32_t k = i; k < end; ++k)
      if (bvh.leaf(k))
        for (std::uint32_t t = 0; t < bvh.leaf_count(k); ++t)
          for (std::uint32_t v : topo.faces()[bvh.leaf_triangles(k)[t]]) vs.push_back(v);
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    closed_vertices_.insert(closed_vertices_.end(), vs.begin(), vs.end());
    closed_vertex_begin_.push_back(static_cast<std::uint32_t>(closed_vertices_.size()));
    i = end;
  }
  closed_ok_.assign(closed_.size(), 0);
  closed_last_.assign(closed_.size(), kUnknown);
  closed_backoff_.assign(closed_.size(), Backoff{});
}

}  // namespace mccd::detail
