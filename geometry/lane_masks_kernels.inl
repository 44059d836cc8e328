// The lane kernels of geometry/lane_masks.h over one instruction set, included by
// geometry/lane_masks.cpp once per set, inside a namespace of its own that defines `Ops`:
//   kLanes                        lanes per register (8, 16 or 32)
//   kLevel                        the SimdLevel
//   Acc                           the lanes apart (or the lanes overlapping) along some slabs
//   Acc slab(lo, hi, olo, ohi)    along one slab: lane j is apart when lo[j] > ohi or olo > hi[j]
//   Acc join(a, b)                along the slabs of both
//   std::uint32_t bits(acc)       lane j's bit set when it overlaps along them
//   Row row(ptr)                  a register's lanes of one row
//   Acc slab_row(lo, hi, olo, ohi) slab() on rows already loaded
//   merge(...)                    LaneKernels::merge_lanes
// No headers here: geometry/lane_masks.cpp includes them before any instruction-set region.

/// The lanes apart along some slab (Ops::bits() then gives those that overlap): slab(s) gives
/// the lanes apart along slab s, joined in a tree (no long chain of dependent operations).
template <unsigned Slabs, class Slab>
typename Ops::Acc apart_along_slabs(const Slab& slab) {
  if constexpr (Slabs == 9) {
    return Ops::join(Ops::join(Ops::join(slab(0), slab(1)), Ops::join(slab(2), slab(3))),
                     Ops::join(Ops::join(slab(4), slab(5)), Ops::join(Ops::join(slab(6), slab(7)), slab(8))));
  } else {
    static_assert(Slabs == 3);
    return Ops::join(Ops::join(slab(0), slab(1)), slab(2));
  }
}

template <unsigned Slabs, unsigned Stride>
void dops_of(const std::int16_t* rows, unsigned n, const CoarseDop* others, unsigned count, std::uint64_t* out) {
  const std::uint64_t valid = n >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
  for (unsigned i = 0; i < count; ++i) {
    const CoarseDop& o = others[i];
    std::uint64_t ov = 0;
    for (unsigned c = 0; c < n; c += Ops::kLanes) {
      const std::int16_t* r = rows + c;
      auto slab = [&](unsigned s) { return Ops::slab(r + s * Stride, r + (Slabs + s) * Stride, o.lo[s], o.hi[s]); };
      ov |= std::uint64_t(Ops::bits(apart_along_slabs<Slabs>(slab))) << c;
    }
    out[i] = ov & valid;
  }
}

template <unsigned Slabs>
void dops_slabs(const std::int16_t* rows, unsigned stride, unsigned n, const CoarseDop* others, unsigned count,
                std::uint64_t* out) {
  switch (stride) {
    case 8: return dops_of<Slabs, 8>(rows, n, others, count, out);
    case 16: return dops_of<Slabs, 16>(rows, n, others, count, out);
    case 32: return dops_of<Slabs, 32>(rows, n, others, count, out);
    default: return dops_of<Slabs, 64>(rows, n, others, count, out);
  }
}

void dops(const std::int16_t* rows, unsigned stride, unsigned n, unsigned slabs, const CoarseDop* others,
          unsigned count, std::uint64_t* out) {
  if (slabs == 9)
    dops_slabs<9>(rows, stride, n, others, count, out);
  else
    dops_slabs<3>(rows, stride, n, others, count, out);
}

/// Block `rows` (runtime stride, n lanes) against the columns j of `chosen` of another block
/// (value r of column j at cols[r * OS + j]): out[j] bit i set when lane i overlaps column j.
/// The block's rows of a register's lanes are loaded once for every column.
template <unsigned Slabs, unsigned OS>
void block_vs_columns(const std::int16_t* rows, unsigned stride, unsigned n, const std::int16_t* cols,
                      std::uint64_t chosen, std::uint64_t* out) {
  const std::uint64_t valid = n >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
  for (std::uint64_t c = chosen; c; c &= c - 1) out[std::countr_zero(c)] = 0;
  for (unsigned c = 0; c < n; c += Ops::kLanes) {
    typename Ops::Row reg[2 * Slabs];
    for (unsigned r = 0; r < 2 * Slabs; ++r) reg[r] = Ops::row(rows + r * stride + c);
    for (std::uint64_t left = chosen; left; left &= left - 1) {
      const unsigned j = static_cast<unsigned>(std::countr_zero(left));
      const std::int16_t* o = cols + j;
      auto slab = [&](unsigned s) { return Ops::slab_row(reg[s], reg[Slabs + s], o[s * OS], o[(Slabs + s) * OS]); };
      out[j] |= std::uint64_t(Ops::bits(apart_along_slabs<Slabs>(slab))) << c;
    }
  }
  for (std::uint64_t c = chosen; c; c &= c - 1) out[std::countr_zero(c)] &= valid;
}

template <unsigned Slabs>
void block_vs_block(const std::int16_t* rows, unsigned stride, unsigned n, const std::int16_t* cols, unsigned cstride,
                    std::uint64_t chosen, std::uint64_t* out) {
  switch (cstride) {
    case 8: return block_vs_columns<Slabs, 8>(rows, stride, n, cols, chosen, out);
    case 16: return block_vs_columns<Slabs, 16>(rows, stride, n, cols, chosen, out);
    case 32: return block_vs_columns<Slabs, 32>(rows, stride, n, cols, chosen, out);
    default: return block_vs_columns<Slabs, 64>(rows, stride, n, cols, chosen, out);
  }
}

template <unsigned Slabs>
void pair_masks_of(const LeafBlocks& a, const LeafBlocks& b, PairMasks& m) {
  m.alive_va = m.alive_vb = m.alive_ea = m.alive_eb = 0;
  if (a.num_vertices) dops_slabs<Slabs>(a.vertices, a.vertex_stride, a.num_vertices, b.leaf, 1, &m.alive_va);
  if (b.num_vertices) dops_slabs<Slabs>(b.vertices, b.vertex_stride, b.num_vertices, a.leaf, 1, &m.alive_vb);
  block_vs_block<Slabs>(b.faces, b.face_stride, b.num_faces, a.vertices, a.vertex_stride, m.alive_va,
                        m.vertex_faces_ab);
  block_vs_block<Slabs>(a.faces, a.face_stride, a.num_faces, b.vertices, b.vertex_stride, m.alive_vb,
                        m.vertex_faces_ba);
  if (a.num_edges) dops_slabs<Slabs>(a.edges, a.edge_stride, a.num_edges, b.leaf, 1, &m.alive_ea);
  if (!m.alive_ea || !b.num_edges) return;
  dops_slabs<Slabs>(b.edges, b.edge_stride, b.num_edges, a.leaf, 1, &m.alive_eb);
  if (!m.alive_eb) return;
  block_vs_block<Slabs>(b.edges, b.edge_stride, b.num_edges, a.edges, a.edge_stride, m.alive_ea, m.edges);
  for (std::uint64_t c = m.alive_ea; c; c &= c - 1) m.edges[std::countr_zero(c)] &= m.alive_eb;
}

void pair_masks(unsigned slabs, const LeafBlocks& a, const LeafBlocks& b, PairMasks& out) {
  if (slabs == 9)
    pair_masks_of<9>(a, b, out);
  else
    pair_masks_of<3>(a, b, out);
}

template <unsigned Slabs>
void self_masks_of(const LeafBlocks& l, std::uint64_t chosen, SelfMasks& m) {
  const std::uint64_t all = l.num_vertices >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << l.num_vertices) - 1;
  block_vs_block<Slabs>(l.faces, l.face_stride, l.num_faces, l.vertices, l.vertex_stride, all, m.vertex_faces);
  block_vs_block<Slabs>(l.edges, l.edge_stride, l.num_edges, l.edges, l.edge_stride, chosen, m.edges);
}

void self_masks(unsigned slabs, const LeafBlocks& l, std::uint64_t chosen, SelfMasks& out) {
  if (slabs == 9)
    self_masks_of<9>(l, chosen, out);
  else
    self_masks_of<3>(l, chosen, out);
}

void merge_lanes(const std::int16_t* rows, unsigned stride, unsigned slabs, const std::uint8_t (*sources)[kMaxLanes],
                 unsigned k, unsigned n, std::int16_t* out, unsigned out_stride) {
  Ops::merge(rows, stride, slabs, sources, k, n, out, out_stride);
}

// The coplanarity cubic of geometry/ccd_stages.h (both_times::coplanarity, cubic_of and
// coplanarity_of), one query per lane of `D` (DOps: W doubles). Every operation is the scalar
// code's, in its order: sums of products as (x + y) + z, differences as written, the cross
// product's components as a.y * b.z - a.z * b.y and so on, the bound as
// (96 u) * ((alpha * beta) * gamma) + 2^-800.
template <bool VF>
void coplanar_quarters_of(const double* x0, const double* x1, const std::uint32_t (*ids)[4],
                          const std::uint8_t* within, std::size_t n, std::uint8_t* quarters) {
  using D = DOps;
  using V = typename D::V;
  constexpr unsigned W = D::kLanes;
  struct P3 {
    V x, y, z;
  };
  auto sub = [](const P3& a, const P3& b) { return P3{D::sub(a.x, b.x), D::sub(a.y, b.y), D::sub(a.z, b.z)}; };
  auto add = [](const P3& a, const P3& b) { return P3{D::add(a.x, b.x), D::add(a.y, b.y), D::add(a.z, b.z)}; };
  auto cross = [](const P3& a, const P3& b) {
    return P3{D::sub(D::mul(a.y, b.z), D::mul(a.z, b.y)), D::sub(D::mul(a.z, b.x), D::mul(a.x, b.z)),
              D::sub(D::mul(a.x, b.y), D::mul(a.y, b.x))};
  };
  auto dot = [](const P3& a, const P3& b) {
    return D::add(D::add(D::mul(a.x, b.x), D::mul(a.y, b.y)), D::mul(a.z, b.z));
  };
  auto amax = [](const P3& a) { return D::max(D::max(D::abs(a.z), D::abs(a.y)), D::abs(a.x)); };
  alignas(64) double buf[2][4][3][W];
  for (std::size_t first = 0; first < n; first += W) {
    const unsigned m = static_cast<unsigned>(n - first < W ? n - first : W);
    for (unsigned i = 0; i < W; ++i) {
      const std::uint32_t* q = ids[first + (i < m ? i : 0)];
      for (unsigned k = 0; k < 4; ++k)
        for (unsigned c = 0; c < 3; ++c) {
          buf[0][k][c][i] = x0[3 * std::size_t(q[k]) + c];
          buf[1][k][c][i] = x1[3 * std::size_t(q[k]) + c];
        }
    }
    P3 p[2][4];
    V mx = D::zero();
    for (unsigned t = 0; t < 2; ++t)
      for (unsigned k = 0; k < 4; ++k) {
        p[t][k] = P3{D::load(buf[t][k][0]), D::load(buf[t][k][1]), D::load(buf[t][k][2])};
        mx = D::max(mx, amax(p[t][k]));
      }
    P3 A[2], B[2], C[2];
    for (unsigned t = 0; t < 2; ++t) {
      A[t] = sub(p[t][1], p[t][0]);
      if constexpr (VF) {
        B[t] = sub(p[t][2], p[t][0]);
        C[t] = sub(p[t][3], p[t][0]);
      } else {
        B[t] = sub(p[t][3], p[t][2]);
        C[t] = sub(p[t][2], p[t][0]);
      }
    }
    // VF: X = B x C, a = A; EE: X = A x B, a = C. Xts: the cross product of time t's first
    // factor and time s's second.
    const P3* U = VF ? B : A;
    const P3* Vv = VF ? C : B;
    const P3* a = VF ? A : C;
    const P3 X00 = cross(U[0], Vv[0]), X11 = cross(U[1], Vv[1]), X01 = cross(U[0], Vv[1]), X10 = cross(U[1], Vv[0]);
    const P3 Xs = add(X01, X10);
    const V c0 = dot(a[0], X00), c3 = dot(a[1], X11);
    const V three = D::set1(3.0);
    const V c1 = D::div(D::add(dot(a[0], Xs), dot(a[1], X00)), three);
    const V c2 = D::div(D::add(dot(a[1], Xs), dot(a[0], X11)), three);
    const V alpha = D::max(amax(A[0]), amax(A[1])), beta = D::max(amax(B[0]), amax(B[1])),
            gamma = D::max(amax(C[0]), amax(C[1]));
    const V ef = D::add(D::mul(D::set1(96 * 0x1p-53), D::mul(D::mul(alpha, beta), gamma)), D::set1(0x1p-800));
    // definite_sign(b, thr) != 0 of geometry/ccd_bernstein.h, per lane
    auto definite = [](const V (&b)[4], V thr) {
      const V nthr = D::neg(thr);
      const unsigned pos = D::gt(b[0], thr) & D::gt(b[1], thr) & D::gt(b[2], thr) & D::gt(b[3], thr);
      const unsigned neg = D::gt(nthr, b[0]) & D::gt(nthr, b[1]) & D::gt(nthr, b[2]) & D::gt(nthr, b[3]);
      return pos | neg;
    };
    // split_half of geometry/ccd_bernstein.h: de Casteljau at 1/2, and the grown bound
    const V half = D::set1(0.5), grow = D::set1(6 * 0x1p-53), tiny = D::set1(0x1p-800);
    auto split = [&](const V (&b)[4], V err, V (&l)[4], V (&r)[4]) {
      const V a0 = D::mul(D::add(b[0], b[1]), half), a1 = D::mul(D::add(b[1], b[2]), half),
              a2 = D::mul(D::add(b[2], b[3]), half);
      const V m0 = D::mul(D::add(a0, a1), half), m1 = D::mul(D::add(a1, a2), half);
      const V mid = D::mul(D::add(m0, m1), half);
      l[0] = b[0], l[1] = a0, l[2] = m0, l[3] = mid;
      r[0] = mid, r[1] = m1, r[2] = a2, r[3] = b[3];
      const V mag = D::max(D::max(D::max(D::max(D::zero(), D::abs(b[0])), D::abs(b[1])), D::abs(b[2])), D::abs(b[3]));
      return D::add(D::add(err, D::mul(grow, mag)), tiny);
    };
    const V f[4] = {c0, c1, c2, c3};
    // FilteredCcd::filter for the points in range (no minimum distance): 0 when the whole
    // cubic is of one sign, else quarters_of (geometry/ccd.cpp): each half of one sign
    // dropped, each quarter of the others kept unless of one sign, among the quarters asked for
    unsigned kept[4] = {0, 0, 0, 0};
    const unsigned whole = definite(f, ef);
    V h[2][4];
    const V eh = split(f, ef, h[0], h[1]);
    for (unsigned i = 0; i < 2; ++i) {
      const unsigned hd = definite(h[i], eh);
      V q[2][4];
      const V eq = split(h[i], eh, q[0], q[1]);
      for (unsigned j = 0; j < 2; ++j) kept[2 * i + j] = ~whole & ~hd & ~definite(q[j], eq);
    }
    const unsigned range = D::ge(mx, D::set1(0x1p-60)) & D::ge(D::set1(0x1p60), mx);
    for (unsigned i = 0; i < m; ++i) {
      const std::uint8_t asked = within[first + i];
      std::uint8_t qs = 0;
      for (unsigned k = 0; k < 4; ++k) qs |= static_cast<std::uint8_t>((kept[k] >> i & 1u) << k);
      quarters[first + i] = (range >> i & 1u) ? static_cast<std::uint8_t>(qs & asked) : kUndecided;
    }
  }
}

void coplanar_quarters(bool vertex_face, const double* x0, const double* x1, const std::uint32_t (*ids)[4],
                       const std::uint8_t* within, std::size_t n, std::uint8_t* quarters) {
  if (vertex_face)
    coplanar_quarters_of<true>(x0, x1, ids, within, n, quarters);
  else
    coplanar_quarters_of<false>(x0, x1, ids, within, n, quarters);
}

const LaneKernels kernels{&dops, &pair_masks, &self_masks, &merge_lanes, &coplanar_quarters, Ops::kLevel};
