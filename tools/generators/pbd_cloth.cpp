#include "generators/pbd_cloth.h"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>

#include <mccd/geometry/disjoint_sets.h>
#include <mccd/geometry/error.h>

namespace mccd::gen {

namespace {

template <class F>
void for_each_index(std::size_t n, F&& f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
  });
}

}  // namespace

PbdCloth::PbdCloth(const TriMesh& mesh, const Options& options) : opt_(options) {
  const std::size_t n = mesh.num_vertices();
  x_.resize(n);
  for (std::size_t i = 0; i < n; ++i) x_[i] = mesh.vertices.point(i);
  rest_ = target_ = p_ = x_;
  v_.assign(n, Vec3::Zero());
  delta_.assign(n, Vec3::Zero());
  key_.assign(n, 0);
  w_.assign(n, 1.0);
  piece_ = detail::vertex_components(n, mesh.faces);
  build_constraints(mesh);
}

void PbdCloth::build_constraints(const TriMesh& mesh) {
  // every edge with the corner opposite it in its triangle; equal edges end up side by side
  struct Side {
    std::uint32_t a, b, opposite;
  };
  std::vector<Side> sides;
  sides.reserve(3 * mesh.num_faces());
  for (const Triangle& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = f[k], b = f[(k + 1) % 3];
      sides.push_back({std::min(a, b), std::max(a, b), f[(k + 2) % 3]});
    }
  std::sort(sides.begin(), sides.end(), [](const Side& s, const Side& t) {
    return s.a != t.a ? s.a < t.a : s.b != t.b ? s.b < t.b : s.opposite < t.opposite;
  });
  std::vector<Constraint> all;
  auto add = [&](std::uint32_t i, std::uint32_t j, double stiffness) {
    if (stiffness > 0) all.push_back({i, j, (rest_[i] - rest_[j]).norm(), stiffness});
  };
  for (std::size_t s = 0; s < sides.size();) {
    std::size_t e = s + 1;
    while (e < sides.size() && sides[e].a == sides[s].a && sides[e].b == sides[s].b) ++e;
    add(sides[s].a, sides[s].b, opt_.stretch);
    if (e - s == 2 && sides[s].opposite != sides[s + 1].opposite) add(sides[s].opposite, sides[s + 1].opposite, opt_.bend);
    s = e;
  }
  // greedy colouring: each constraint takes the first batch neither of its vertices is in yet
  std::vector<std::uint64_t> used(x_.size(), 0);
  for (const Constraint& c : all) {
    const std::uint64_t taken = used[c.i] | used[c.j];
    if (taken == ~std::uint64_t{0}) throw Error("PbdCloth: a vertex has more than 64 constraint colours");
    const int colour = std::countr_one(taken);
    if (std::size_t(colour) >= batches_.size()) batches_.resize(colour + 1);
    batches_[colour].push_back(c);
    used[c.i] |= std::uint64_t{1} << colour;
    used[c.j] |= std::uint64_t{1} << colour;
  }
}

void PbdCloth::pin(std::size_t i) {
  w_[i] = 0;
  v_[i] = Vec3::Zero();
  target_[i] = x_[i];
}

void PbdCloth::add_velocity(const Vec3& dv) {
  for (std::size_t i = 0; i < size(); ++i)
    if (w_[i] > 0) v_[i] += dv;
}

void PbdCloth::substep(double dt, const Collider& collide) {
  const double keep = std::max(0.0, 1.0 - opt_.damping * dt);
  for_each_index(size(), [&](std::size_t i) {
    if (w_[i] > 0) {
      v_[i] = keep * (v_[i] + dt * opt_.gravity);
      p_[i] = x_[i] + dt * v_[i];
    } else {
      p_[i] = target_[i];
    }
  });
  auto collide_all = [&] {
    for_each_index(size(), [&](std::size_t i) {
      if (w_[i] > 0) collide(p_[i], x_[i]);
    });
  };
  for (int it = 0; it < opt_.iterations; ++it) {
    for (const std::vector<Constraint>& batch : batches_)
      for_each_index(batch.size(), [&](std::size_t k) {
        const Constraint& c = batch[k];
        const double wsum = w_[c.i] + w_[c.j];
        if (wsum == 0) return;
        const Vec3 d = p_[c.j] - p_[c.i];
        const double len = d.norm();
        if (len < 1e-12) return;
        const Vec3 corr = (c.stiffness * (len - c.length) / (wsum * len)) * d;
        p_[c.i] += w_[c.i] * corr;
        p_[c.j] -= w_[c.j] * corr;
      });
    collide_all();
  }
  if (opt_.repulsion > 0) {
    repel();
    collide_all();
  }
  for_each_index(size(), [&](std::size_t i) {
    if (w_[i] > 0) v_[i] = (p_[i] - x_[i]) / dt;
    x_[i] = p_[i];
  });
}

void PbdCloth::repel() {
  const double h = opt_.repulsion, exclude2 = 4 * h * h;
  const std::size_t n = size();
  const int bits = std::bit_width(std::max<std::size_t>(2 * n, 16) - 1);
  // cells of side h, packed 21 bits per axis; a multiplicative hash picks the bucket
  auto key_of = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    constexpr std::int64_t bias = 1 << 20, mask = (1 << 21) - 1;
    return std::uint64_t((x + bias) & mask) << 42 | std::uint64_t((y + bias) & mask) << 21 | std::uint64_t((z + bias) & mask);
  };
  auto bucket_of = [bits](std::uint64_t key) { return std::size_t((key * 0x9E3779B97F4A7C15ull) >> (64 - bits)); };
  cell_.resize(n);
  for_each_index(n, [&](std::size_t i) {
    for (int k = 0; k < 3; ++k) cell_[i][k] = std::int32_t(std::floor(p_[i][k] / h));
    key_[i] = key_of(cell_[i][0], cell_[i][1], cell_[i][2]);
  });
  // counting sort of the vertices by bucket (serial: the order is part of the result)
  const std::size_t table = std::size_t(1) << bits;
  bucket_start_.assign(table + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++bucket_start_[bucket_of(key_[i]) + 1];
  std::partial_sum(bucket_start_.begin(), bucket_start_.end(), bucket_start_.begin());
  bucket_items_.resize(n);
  {
    std::vector<std::uint32_t> fill(bucket_start_.begin(), bucket_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) bucket_items_[fill[bucket_of(key_[i])]++] = std::uint32_t(i);
  }
  for_each_index(n, [&](std::size_t i) {
    Vec3 push = Vec3::Zero();
    if (w_[i] > 0)
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const std::uint64_t key = key_of(cell_[i][0] + dx, cell_[i][1] + dy, cell_[i][2] + dz);
            const std::size_t b = bucket_of(key);
            for (std::uint32_t s = bucket_start_[b]; s < bucket_start_[b + 1]; ++s) {
              const std::uint32_t j = bucket_items_[s];
              if (j == i || key_[j] != key) continue;  // another cell hashed to this bucket
              const Vec3 r = p_[i] - p_[j];
              const double d2 = r.squaredNorm();
              if (d2 >= h * h || d2 < 1e-24) continue;
              if (piece_[i] == piece_[j] && (rest_[i] - rest_[j]).squaredNorm() < exclude2) continue;
              const double d = std::sqrt(d2);
              push += (w_[i] / (w_[i] + w_[j]) * (h - d) / d) * r;
            }
          }
    delta_[i] = push;
  });
  for_each_index(n, [&](std::size_t i) { p_[i] += delta_[i]; });
}

void PbdCloth::write(Positions& out, std::size_t offset) const {
  for (std::size_t i = 0; i < size(); ++i) out.set_point(offset + i, x_[i]);
}

}  // namespace mccd::gen
