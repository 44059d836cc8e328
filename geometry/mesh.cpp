#include "geometry/mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "geometry/error.h"

namespace mccd {

void validate_mesh(const TriMesh& mesh) {
  const std::string name = mesh.name.empty() ? std::string("mesh") : mesh.name;
  const std::size_t nv = mesh.num_vertices();
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Triangle& t = mesh.faces[f];
    for (int k = 0; k < 3; ++k) {
      if (t[k] >= nv)
        throw Error(name + ": face " + std::to_string(f) + ": vertex index " + std::to_string(t[k]) +
                    " out of range [0, " + std::to_string(nv) + ")");
    }
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw Error(name + ": face " + std::to_string(f) + ": repeated vertex index (" + std::to_string(t[0]) + ", " +
                  std::to_string(t[1]) + ", " + std::to_string(t[2]) + ")");
  }
  validate_positions(mesh.vertices, nv, name);
}

void validate_positions(const Eigen::Ref<const Positions>& positions, std::size_t num_vertices,
                        const std::string& what) {
  if (static_cast<std::size_t>(positions.rows()) != num_vertices)
    throw Error(what + ": has " + std::to_string(positions.rows()) + " vertices, expected " +
                std::to_string(num_vertices));
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(positions(v, c)))
        throw Error(what + ": vertex " + std::to_string(v) + ": coordinate " + "xyz"[c] + " is not finite (" +
                    std::to_string(positions(v, c)) + ")");
}

MeshTopology::MeshTopology(std::size_t num_vertices, const std::vector<Triangle>& faces) : faces_(faces) {
  const std::size_t nf = faces.size();
  // vertex -> faces, CSR
  vertex_face_offsets_.assign(num_vertices + 1, 0);
  for (const Triangle& t : faces)
    for (auto v : t) ++vertex_face_offsets_[v + 1];
  for (std::size_t v = 0; v < num_vertices; ++v) vertex_face_offsets_[v + 1] += vertex_face_offsets_[v];
  vertex_faces_.resize(vertex_face_offsets_.back());
  {
    std::vector<std::uint32_t> fill(vertex_face_offsets_.begin(), vertex_face_offsets_.end() - 1);
    for (std::size_t f = 0; f < nf; ++f)
      for (auto v : faces[f]) vertex_faces_[fill[v]++] = static_cast<std::uint32_t>(f);
  }
  // half-edges keyed by (max, min), then unique: gives the libigl order.
  struct HalfEdge {
    std::uint32_t hi, lo, face, corner;
  };
  std::vector<HalfEdge> half(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (std::uint32_t k = 0; k < 3; ++k) {
      std::uint32_t a = faces[f][k], b = faces[f][(k + 1) % 3];
      half[3 * f + k] = {std::max(a, b), std::min(a, b), static_cast<std::uint32_t>(f), k};
    }
  std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.hi != y.hi ? x.hi < y.hi : (x.lo != y.lo ? x.lo < y.lo : x.face < y.face);
  });
  // Half-edges of one edge are adjacent after the sort, ordered by face: the CSR of edge
  // faces falls out directly.
  face_edges_.assign(nf, {0, 0, 0});
  edge_faces_.reserve(half.size());
  for (std::size_t i = 0; i < half.size(); ++i) {
    if (i == 0 || half[i].hi != half[i - 1].hi || half[i].lo != half[i - 1].lo) {
      edges_.push_back({half[i].lo, half[i].hi});
      edge_face_offsets_.push_back(static_cast<std::uint32_t>(i));
    }
    const auto e = static_cast<std::uint32_t>(edges_.size() - 1);
    edge_faces_.push_back(half[i].face);
    face_edges_[half[i].face][half[i].corner] = e;
  }
  edge_face_offsets_.push_back(static_cast<std::uint32_t>(half.size()));
}

std::size_t MeshTopology::num_boundary_edges() const {
  std::size_t n = 0;
  for (std::size_t e = 0; e < edges_.size(); ++e) n += edge_face_count(e) == 1;
  return n;
}

std::size_t MeshTopology::num_nonmanifold_edges() const {
  std::size_t n = 0;
  for (std::size_t e = 0; e < edges_.size(); ++e) n += edge_face_count(e) > 2;
  return n;
}

std::int64_t MeshTopology::find_edge(std::uint32_t a, std::uint32_t b) const {
  const Edge key{std::min(a, b), std::max(a, b)};
  auto it = std::lower_bound(edges_.begin(), edges_.end(), key, [](const Edge& x, const Edge& y) {
    return x[1] != y[1] ? x[1] < y[1] : x[0] < y[0];
  });
  if (it == edges_.end() || *it != key) return -1;
  return it - edges_.begin();
}

std::size_t count_zero_area_faces(const TriMesh& mesh) {
  std::size_t n = 0;
  for (const Triangle& t : mesh.faces) {
    Vec3 a = mesh.vertices.row(t[0]), b = mesh.vertices.row(t[1]), c = mesh.vertices.row(t[2]);
    if ((b - a).cross(c - a).squaredNorm() == 0.0) ++n;
  }
  return n;
}

Bounds3 bounding_box(const Eigen::Ref<const Positions>& positions) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Bounds3 b{Vec3::Constant(inf), Vec3::Constant(-inf)};
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    b.min = b.min.cwiseMin(positions.row(v).transpose());
    b.max = b.max.cwiseMax(positions.row(v).transpose());
  }
  return b;
}

TriMesh make_grid_mesh(int n, double size) {
  TriMesh m;
  m.name = "grid" + std::to_string(n);
  const int nv = n + 1;
  m.vertices.resize(nv * nv, 3);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nv; ++i)
      m.vertices.row(j * nv + i) << size * (double(i) / n - 0.5), size * (double(j) / n - 0.5), 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      auto a = std::uint32_t(j * nv + i), b = a + 1, c = a + std::uint32_t(nv), d = c + 1;
      // alternate the diagonal so the cloth has no preferred shear direction
      if ((i + j) % 2 == 0) {
        m.faces.push_back({a, b, d});
        m.faces.push_back({a, d, c});
      } else {
        m.faces.push_back({a, b, c});
        m.faces.push_back({b, d, c});
      }
    }
  return m;
}

TriMesh make_sphere_mesh(int rings, int segments, double radius, const Vec3& centre) {
  TriMesh m;
  m.name = "sphere";
  const int nv = 2 + (rings - 1) * segments;
  m.vertices.resize(nv, 3);
  m.vertices.row(0) = (centre + Vec3(0, 0, radius)).transpose();
  for (int r = 1; r < rings; ++r) {
    const double th = std::numbers::pi * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double ph = 2 * std::numbers::pi * s / segments;
      m.vertices.row(1 + (r - 1) * segments + s) =
          (centre + radius * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th))).transpose();
    }
  }
  const auto south = std::uint32_t(nv - 1);
  m.vertices.row(south) = (centre + Vec3(0, 0, -radius)).transpose();
  auto idx = [&](int r, int s) { return std::uint32_t(1 + (r - 1) * segments + (s % segments)); };
  for (int s = 0; s < segments; ++s) m.faces.push_back({0, idx(1, s), idx(1, s + 1)});
  for (int r = 1; r < rings - 1; ++r)
    for (int s = 0; s < segments; ++s) {
      m.faces.push_back({idx(r, s), idx(r + 1, s), idx(r + 1, s + 1)});
      m.faces.push_back({idx(r, s), idx(r + 1, s + 1), idx(r, s + 1)});
    }
  for (int s = 0; s < segments; ++s) m.faces.push_back({idx(rings - 1, s), south, idx(rings - 1, s + 1)});
  return m;
}

}  // namespace mccd
