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
/// The block's rows of a register's lanes are loaded once for every column (into registers:
/// the loop is unrolled), and a block of one register's lanes writes each mask once. Inlined
/// into the kernels that call it: most calls test a few columns.
template <unsigned Slabs, unsigned OS>
[[gnu::always_inline]] inline void block_vs_columns(const std::int16_t* rows, unsigned stride, unsigned n,
                                                    const std::int16_t* cols, std::uint64_t chosen,
                                                    std::uint64_t* out) {
  const std::uint64_t valid = n >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
  auto columns = [&](unsigned c, auto&& write) {  // every column against lanes [c, c + kLanes)
    typename Ops::Row reg[2 * Slabs];
#pragma GCC unroll 18
    for (unsigned r = 0; r < 2 * Slabs; ++r) reg[r] = Ops::row(rows + r * stride + c);
    for (std::uint64_t left = chosen; left; left &= left - 1) {
      const unsigned j = static_cast<unsigned>(std::countr_zero(left));
      const std::int16_t* o = cols + j;
      auto slab = [&](unsigned s) { return Ops::slab_row(reg[s], reg[Slabs + s], o[s * OS], o[(Slabs + s) * OS]); };
      write(j, std::uint64_t(Ops::bits(apart_along_slabs<Slabs>(slab))));
    }
  };
  if (n <= Ops::kLanes) {
    columns(0, [&](unsigned j, std::uint64_t bits) { out[j] = bits & valid; });
    return;
  }
  for (std::uint64_t c = chosen; c; c &= c - 1) out[std::countr_zero(c)] = 0;
  for (unsigned c = 0; c < n; c += Ops::kLanes)
    columns(c, [&](unsigned j, std::uint64_t bits) { out[j] |= bits << c; });
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

// Vectors of three coordinates, one query per lane of DOps (W doubles), and the scalar code's
// vector operations (geometry/ccd_bernstein.h) in its order: sums of products as (x + y) + z,
// differences as written, the cross product's components as a.y * b.z - a.z * b.y and so on.
struct P3 {
  DOps::V x, y, z;
};
inline P3 sub3(const P3& a, const P3& b) { return {DOps::sub(a.x, b.x), DOps::sub(a.y, b.y), DOps::sub(a.z, b.z)}; }
inline P3 add3(const P3& a, const P3& b) { return {DOps::add(a.x, b.x), DOps::add(a.y, b.y), DOps::add(a.z, b.z)}; }
inline P3 scale3(const P3& a, DOps::V s) { return {DOps::mul(a.x, s), DOps::mul(a.y, s), DOps::mul(a.z, s)}; }
inline P3 abs3(const P3& a) { return {DOps::abs(a.x), DOps::abs(a.y), DOps::abs(a.z)}; }
inline P3 cross3(const P3& a, const P3& b) {
  using D = DOps;
  return {D::sub(D::mul(a.y, b.z), D::mul(a.z, b.y)), D::sub(D::mul(a.z, b.x), D::mul(a.x, b.z)),
          D::sub(D::mul(a.x, b.y), D::mul(a.y, b.x))};
}
/// geometry/ccd_bernstein.h's across: the cross product's terms added instead of subtracted
inline P3 across3(const P3& a, const P3& b) {
  using D = DOps;
  return {D::add(D::mul(a.y, b.z), D::mul(a.z, b.y)), D::add(D::mul(a.z, b.x), D::mul(a.x, b.z)),
          D::add(D::mul(a.x, b.y), D::mul(a.y, b.x))};
}
inline DOps::V dot3(const P3& a, const P3& b) {
  using D = DOps;
  return D::add(D::add(D::mul(a.x, b.x), D::mul(a.y, b.y)), D::mul(a.z, b.z));
}
inline DOps::V amax3(const P3& a) { return DOps::max(DOps::max(DOps::abs(a.z), DOps::abs(a.y)), DOps::abs(a.x)); }
/// (1 - tau) a0 + tau a1 as the scalar snapshots compute it: a0 * t1 + a1 * tau
inline P3 lerp3(const P3& a0, const P3& a1, DOps::V t1, DOps::V tau) { return add3(scale3(a0, t1), scale3(a1, tau)); }

/// Points ids[i][k] of up to W items (ids[0..m), the rest repeating the first) at t = 0 and
/// t = 1, lane i: each coordinate of a point in one gather (offsets 3 id + coordinate).
template <unsigned K, class D = DOps>  // D: a dependent name, so that only its level's branch is compiled
inline void gather_points(const double* x0, const double* x1, const std::uint32_t (*ids)[K], unsigned m,
                          P3 (&p)[2][K]) {
  constexpr unsigned W = D::kLanes;
  if constexpr (requires { typename D::Offsets; }) {  // the offsets in vector lanes
    typename D::Offsets at[K];
    D::template offsets<K>(ids, m, at);
    for (unsigned k = 0; k < K; ++k) {
      p[0][k] = P3{D::gather_at(x0, at[k]), D::gather_at(x0 + 1, at[k]), D::gather_at(x0 + 2, at[k])};
      p[1][k] = P3{D::gather_at(x1, at[k]), D::gather_at(x1 + 1, at[k]), D::gather_at(x1 + 2, at[k])};
    }
  } else {
    alignas(64) std::int64_t at[K][W];
    for (unsigned i = 0; i < W; ++i) {
      const std::uint32_t* q = ids[i < m ? i : 0];
      for (unsigned k = 0; k < K; ++k) at[k][i] = 3 * std::int64_t(q[k]);
    }
    for (unsigned k = 0; k < K; ++k) {
      p[0][k] = P3{D::gather(x0, at[k]), D::gather(x0 + 1, at[k]), D::gather(x0 + 2, at[k])};
      p[1][k] = P3{D::gather(x1, at[k]), D::gather(x1 + 1, at[k]), D::gather(x1 + 2, at[k])};
    }
  }
}

/// The points of up to W queries (ids[0..m), the rest repeating the first) at t = 0 and t = 1.
struct LanePoints {
  P3 p[2][4];
};
inline void gather(const double* x0, const double* x1, const std::uint32_t (*ids)[4], unsigned m, LanePoints& out) {
  gather_points<4>(x0, x1, ids, m, out.p);
}

/// The coplanarity cubic of geometry/ccd_stages.h (both_times::coplanarity, cubic_of and
/// coplanarity_of) per lane, with what stage (c) reads of the Setup: the difference vectors
/// A, B, C at t = 0 and 1 (VF: corners minus the vertex; EE: da, db, w), their magnitudes, the
/// cubic's Bernstein coefficients and its bound (96 u) * ((alpha * beta) * gamma) + 2^-800,
/// and the points' largest absolute coordinate.
struct LaneCubic {
  P3 A[2], B[2], C[2];
  DOps::V alpha, beta, gamma, f[4], ef, mx;
};
template <bool VF>
void cubic_lanes(const LanePoints& pts, LaneCubic& q) {
  using D = DOps;
  q.mx = D::zero();
  for (unsigned t = 0; t < 2; ++t)
    for (unsigned k = 0; k < 4; ++k) q.mx = D::max(q.mx, amax3(pts.p[t][k]));
  for (unsigned t = 0; t < 2; ++t) {
    const P3* p = pts.p[t];
    q.A[t] = sub3(p[1], p[0]);
    if constexpr (VF) {
      q.B[t] = sub3(p[2], p[0]);
      q.C[t] = sub3(p[3], p[0]);
    } else {
      q.B[t] = sub3(p[3], p[2]);
      q.C[t] = sub3(p[2], p[0]);
    }
  }
  // VF: X = B x C, a = A; EE: X = A x B, a = C. Xts: the cross product of time t's first
  // factor and time s's second.
  const P3* U = VF ? q.B : q.A;
  const P3* Vv = VF ? q.C : q.B;
  const P3* a = VF ? q.A : q.C;
  const P3 X00 = cross3(U[0], Vv[0]), X11 = cross3(U[1], Vv[1]), X01 = cross3(U[0], Vv[1]), X10 = cross3(U[1], Vv[0]);
  const P3 Xs = add3(X01, X10);
  const auto three = D::set1(3.0);
  q.f[0] = dot3(a[0], X00), q.f[3] = dot3(a[1], X11);
  q.f[1] = D::div(D::add(dot3(a[0], Xs), dot3(a[1], X00)), three);
  q.f[2] = D::div(D::add(dot3(a[1], Xs), dot3(a[0], X11)), three);
  q.alpha = D::max(amax3(q.A[0]), amax3(q.A[1]));
  q.beta = D::max(amax3(q.B[0]), amax3(q.B[1]));
  q.gamma = D::max(amax3(q.C[0]), amax3(q.C[1]));
  q.ef = D::add(D::mul(D::set1(96 * 0x1p-53), D::mul(D::mul(q.alpha, q.beta), q.gamma)), D::set1(0x1p-800));
}

/// The lanes whose points need no scaling (largest coordinate in [2^-60, 2^60]: `load` of
/// geometry/ccd_setup.h keeps them as they are).
inline unsigned in_range(const LaneCubic& q) {
  return DOps::ge(q.mx, DOps::set1(0x1p-60)) & DOps::ge(DOps::set1(0x1p60), q.mx);
}

/// one_sign_change of geometry/ccd_fast.h per lane: the end coefficients certainly of opposite
/// signs (beyond e) and no pattern + - + (- + -) possible.
inline unsigned one_sign_change_lanes(const DOps::V (&c)[4], DOps::V e) {
  using D = DOps;
  const DOps::V ne = D::neg(e);
  return (D::gt(c[0], e) & D::gt(ne, c[3]) & (D::ge(c[1], e) | D::ge(ne, c[2]))) |
         (D::gt(ne, c[0]) & D::gt(c[3], e) & (D::ge(ne, c[1]) | D::ge(c[2], e)));
}
/// definite_sign(c, e) != 0 of geometry/ccd_bernstein.h per lane.
inline unsigned definite_lanes(const DOps::V (&c)[4], DOps::V e) {
  using D = DOps;
  const DOps::V ne = D::neg(e);
  return (D::gt(c[0], e) & D::gt(c[1], e) & D::gt(c[2], e) & D::gt(c[3], e)) |
         (D::gt(ne, c[0]) & D::gt(ne, c[1]) & D::gt(ne, c[2]) & D::gt(ne, c[3]));
}

template <bool VF>
void coplanar_quarters_of(const double* x0, const double* x1, const std::uint32_t (*ids)[4],
                          const std::uint8_t* within, std::size_t n, std::uint8_t* quarters) {
  using D = DOps;
  using V = typename D::V;
  constexpr unsigned W = D::kLanes;
  for (std::size_t first = 0; first < n; first += W) {
    const unsigned m = static_cast<unsigned>(n - first < W ? n - first : W);
    LanePoints pts;
    gather(x0, x1, ids + first, m, pts);
    LaneCubic q;
    cubic_lanes<VF>(pts, q);
    const V ef = q.ef;
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
    const V f[4] = {q.f[0], q.f[1], q.f[2], q.f[3]};
    // FilteredCcd::filter for the points in range (no minimum distance): 0 when the whole
    // cubic is of one sign, else quarters_of (geometry/ccd.cpp): each half of one sign
    // dropped, each quarter of the others kept unless of one sign, among the quarters asked for
    unsigned kept[4] = {0, 0, 0, 0};
    const unsigned whole = definite_lanes(f, ef);
    // Where every pair's cubic is of one sign over the whole step (most registers of a
    // sub-step's pairs), no quarter is kept and the halves are not needed.
    const unsigned active = m >= 32 ? ~0u : (1u << m) - 1;
    if ((whole & active) != active) {
      V h[2][4];
      const V eh = split(f, ef, h[0], h[1]);
      for (unsigned i = 0; i < 2; ++i) {
        const unsigned hd = definite_lanes(h[i], eh);
        V qh[2][4];
        const V eq = split(h[i], eh, qh[0], qh[1]);
        for (unsigned j = 0; j < 2; ++j) kept[2 * i + j] = ~whole & ~hd & ~definite_lanes(qh[j], eq);
      }
    }
    const unsigned range = in_range(q);
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

/// The cubic and the inside functions at the instant tau per lane: KindOps::snapshot of
/// geometry/ccd_stages.h (vertex_face::snapshot, edge_edge::snapshot). EE reads the
/// separation pairs D[1] (b0 - a1) and D[2] (b1 - a0) at t = 0 and 1 (`v`, `z`).
struct LaneSnap {
  DOps::V f, g[4];
};
template <bool VF>
LaneSnap snapshot_lanes(const LaneCubic& q, const P3 (&v)[2], const P3 (&z)[2], DOps::V tau) {
  using D = DOps;
  const DOps::V t1 = D::sub(D::set1(1.0), tau);
  LaneSnap s;
  if constexpr (VF) {
    const P3 A = lerp3(q.A[0], q.A[1], t1, tau), B = lerp3(q.B[0], q.B[1], t1, tau), C = lerp3(q.C[0], q.C[1], t1, tau);
    const P3 X = cross3(B, C), Y = cross3(C, A), Z = cross3(A, B);
    const P3 n = add3(add3(X, Y), Z);
    s.f = dot3(A, X);
    s.g[0] = dot3(n, X), s.g[1] = dot3(n, Y), s.g[2] = dot3(n, Z), s.g[3] = D::zero();
  } else {
    const P3 da = lerp3(q.A[0], q.A[1], t1, tau), db = lerp3(q.B[0], q.B[1], t1, tau), w = lerp3(q.C[0], q.C[1], t1, tau);
    const P3 vv = lerp3(v[0], v[1], t1, tau), zz = lerp3(z[0], z[1], t1, tau);
    const P3 e = cross3(da, db);
    s.f = dot3(w, e);
    s.g[0] = dot3(cross3(w, db), e), s.g[1] = D::neg(dot3(cross3(vv, db), e));
    s.g[2] = dot3(cross3(w, da), e), s.g[3] = dot3(cross3(da, zz), e);
  }
  return s;
}

/// KindOps::f_error: 16 u times the triple product's magnitude at tau, plus 2^-800.
inline DOps::V f_error_lanes(const LaneCubic& q, DOps::V tau) {
  using D = DOps;
  const DOps::V t1 = D::sub(D::set1(1.0), tau);
  const P3 A = lerp3(abs3(q.A[0]), abs3(q.A[1]), t1, tau), B = lerp3(abs3(q.B[0]), abs3(q.B[1]), t1, tau),
           C = lerp3(abs3(q.C[0]), abs3(q.C[1]), t1, tau);
  return D::add(D::mul(D::set1(16 * 0x1p-53), dot3(A, across3(B, C))), D::set1(0x1p-800));
}

/// What the fast path needs of a query besides its cubic: the inside functions' magnitudes M_i
/// (KindOps::inside_magnitudes) and, for EE, the separation pairs its snapshots read.
struct LaneInside {
  P3 vz[2][2];  // EE: b0 - a1 and b1 - a0 at t = 0 and 1
  DOps::V M[4];
};
template <bool VF>
void inside_lanes(const LanePoints& pts, const LaneCubic& q, LaneInside& in) {
  using D = DOps;
  if constexpr (VF) {
    const DOps::V bg = D::mul(q.beta, q.gamma), ga = D::mul(q.gamma, q.alpha), ab = D::mul(q.alpha, q.beta);
    const DOps::V s2 = D::mul(D::set1(12.0), D::add(D::add(bg, ga), ab));
    in.M[0] = D::mul(s2, bg), in.M[1] = D::mul(s2, ga), in.M[2] = D::mul(s2, ab), in.M[3] = D::zero();
    in.vz[0][0] = in.vz[0][1] = in.vz[1][0] = in.vz[1][1] = P3{D::zero(), D::zero(), D::zero()};  // unused
  } else {
    for (unsigned t = 0; t < 2; ++t)
      in.vz[0][t] = sub3(pts.p[t][2], pts.p[t][1]), in.vz[1][t] = sub3(pts.p[t][3], pts.p[t][0]);
    const DOps::V nu = D::max(amax3(in.vz[0][0]), amax3(in.vz[0][1])),
                  zeta = D::max(amax3(in.vz[1][0]), amax3(in.vz[1][1]));
    const DOps::V ab12 = D::mul(D::mul(D::set1(12.0), q.alpha), q.beta);
    in.M[0] = D::mul(ab12, D::mul(q.beta, q.gamma)), in.M[1] = D::mul(ab12, D::mul(nu, q.beta));
    in.M[2] = D::mul(ab12, D::mul(q.gamma, q.alpha)), in.M[3] = D::mul(ab12, D::mul(q.alpha, zeta));
  }
}

/// fast_root of geometry/ccd_fast.h per lane of `live`, on the piece [x, y] whose cubic has
/// the Bernstein coefficients p (exactly one sign change): root_estimate of
/// geometry/ccd_bernstein.h, the bracket [a, b], the certain signs of the cubic there, the
/// inside functions over it. `hit` (time in `toi`): a certified contact whose time needs no
/// bisection; `miss`: no contact at this root; the other lanes of `live` stay undecided.
struct RootLanes {
  unsigned hit = 0, miss = 0;
  DOps::V toi;
};
template <bool VF>
RootLanes fast_root_lanes(const LaneCubic& q, const LaneInside& in, const DOps::V (&p)[4], DOps::V x, DOps::V y,
                          unsigned live) {
  using D = DOps;
  using V = DOps::V;
  constexpr unsigned kAll = (1u << D::kLanes) - 1;
  const V zero = D::zero(), one = D::set1(1.0), three = D::set1(3.0);
  const V c0 = p[0], c1 = p[1], c2 = p[2], c3 = p[3], ef = q.ef, nef = D::neg(ef);
  RootLanes out;
  out.toi = zero;
  // root_estimate(p, x, y, slope)
  const unsigned neg0 = D::gt(zero, c0);
  V sl = zero, sr = one, s = D::set1(0.5), d = zero;
  unsigned started = 0;
  for (int k = 0; k < 3; ++k) {
    const unsigned change = (D::gt(zero, p[k + 1]) ^ neg0) & ~started & kAll;
    if (!change) continue;
    const V qk = D::div(D::add(D::set1(k), D::div(p[k], D::sub(p[k], p[k + 1]))), three);
    s = D::select(change & D::gt(qk, zero) & D::gt(one, qk), qk, s);
    started |= change;
  }
  unsigned active = live;
  for (int it = 0; it < 40 && active; ++it) {
    const V b0 = D::add(c0, D::mul(s, D::sub(c1, c0))), b1 = D::add(c1, D::mul(s, D::sub(c2, c1))),
            b2 = D::add(c2, D::mul(s, D::sub(c3, c2)));
    const V e0 = D::add(b0, D::mul(s, D::sub(b1, b0))), e1 = D::add(b1, D::mul(s, D::sub(b2, b1)));
    const V v = D::add(e0, D::mul(s, D::sub(e1, e0)));
    const V dn = D::mul(three, D::sub(e1, e0));
    d = D::select(active, dn, d);
    active &= ~D::eq(v, zero);
    const unsigned left = ~(D::gt(zero, v) ^ neg0);  // (v < 0) == neg0
    sl = D::select(active & left, s, sl);
    sr = D::select(active & ~left, s, sr);
    const V step = D::div(v, dn);
    const V ns = D::sub(s, step);
    const unsigned converged = active & D::ge(D::set1(0x1p-40), D::abs(step));
    const V clamped = D::select(D::gt(sl, ns), sl, D::select(D::gt(ns, sr), sr, ns));  // std::clamp(ns, sl, sr)
    s = D::select(converged, clamped, s);
    active &= ~converged;
    const V bisect = D::mul(D::set1(0.5), D::add(sl, sr));
    s = D::select(active, D::select(D::gt(ns, sl) & D::gt(sr, ns), ns, bisect), s);
    active &= ~D::ge(D::set1(0x1p-52), D::sub(sr, sl));
  }
  const V slope = D::div(d, D::sub(y, x));
  const V r = D::add(x, D::mul(s, D::sub(y, x)));
  // the bracket [a, b] of half-width 2 h around r, h a power of two from the slope
  const V hw = D::div(D::mul(D::set1(4.0), ef), D::abs(slope));
  unsigned ok = live & D::ge(D::set1(0x1p-20), hw);
  const V p2 = D::exponent(hw);
  const V h = D::select(D::gt(D::set1(0x1p-50), hw), D::set1(0x1p-50), D::select(D::eq(p2, hw), p2, D::mul(D::set1(2.0), p2)));
  const V k = D::floor_nonneg(D::div(r, h));
  const V below = D::mul(D::sub(k, D::set1(2.0)), h), above = D::mul(D::add(k, D::set1(2.0)), h);
  const V a = D::select(D::gt(below, x), below, x);  // std::max(x, below)
  const V b = D::select(D::gt(y, above), above, y);  // std::min(y, above)
  const LaneSnap sa = snapshot_lanes<VF>(q, in.vz[0], in.vz[1], a), sb = snapshot_lanes<VF>(q, in.vz[0], in.vz[1], b);
  // certain signs at a (that of p's c0) and at b (the other): against ef, else f_error there
  const V fea = f_error_lanes(q, a), feb = f_error_lanes(q, b);
  const unsigned neg_a = D::gt(nef, sa.f) | D::gt(D::neg(fea), sa.f), pos_a = D::gt(sa.f, ef) | D::gt(sa.f, fea);
  const unsigned neg_b = D::gt(nef, sb.f) | D::gt(D::neg(feb), sb.f), pos_b = D::gt(sb.f, ef) | D::gt(sb.f, feb);
  ok &= ((neg0 & neg_a) | (~neg0 & pos_a)) & ((neg0 & pos_b) | (~neg0 & neg_b));
  // the inside functions over [a, b]
  const V w = D::sub(b, a);
  const V cw = D::add(D::set1(24 * 0x1p-53), D::mul(D::set1(7.0), D::mul(w, w)));
  constexpr int kInside = VF ? 3 : 4;
  unsigned negative = 0, positive = kAll;
  for (int i = 0; i < kInside; ++i) {
    const V e = D::add(D::mul(in.M[i], cw), D::set1(2 * 0x1p-800)), ne = D::neg(e);
    negative |= D::gt(ne, sa.g[i]) & D::gt(ne, sb.g[i]);
    positive &= D::gt(sa.g[i], e) & D::gt(sb.g[i], e);
  }
  out.miss = ok & negative;
  // toi on the grid of G = 2^-32: lo <= r; decided here when [lo, hi] is one grid cell
  const V G = D::set1(0x1p-32);
  const V lo = D::mul(D::floor_nonneg(D::div(a, G)), G);
  const V bG = D::div(b, G), fb = D::floor_nonneg(bG);
  const V hi = D::mul(D::select(D::gt(bG, fb), D::add(fb, one), fb), G);
  out.hit = ok & ~negative & positive & ~D::gt(D::sub(hi, lo), G);
  out.toi = lo;
  return out;
}

/// split_points of geometry/ccd_fast.h per lane: estimates of the cubic's critical points in
/// (0, 1) on the grid of 2^-24, in order (m0 < m1 where `two`), else 1/2.
inline unsigned split_points_lanes(const DOps::V (&f)[4], DOps::V& m0, DOps::V& m1) {
  using D = DOps;
  using V = DOps::V;
  const V zero = D::zero(), two = D::set1(2.0);
  const V d0 = D::sub(f[1], f[0]), d1 = D::sub(f[2], f[1]), d2 = D::sub(f[3], f[2]);
  const V qa = D::add(D::sub(d0, D::mul(two, d1)), d2), qb = D::mul(two, D::sub(d1, d0)), qc = d0;
  const unsigned linear = D::eq(qa, zero);
  const V disc = D::sub(D::mul(qb, qb), D::mul(D::mul(D::set1(4.0), qa), qc));
  const V qq = D::mul(D::set1(-0.5), D::add(qb, D::copysign(D::sqrt(disc), qb)));
  // the roots: -qc / qb (qa = 0, qb != 0); q / qa and, when q != 0, qc / q (disc >= 0)
  const V r0 = D::select(linear, D::div(D::neg(qc), qb), D::div(qq, qa)), r1 = D::div(qc, qq);
  const unsigned has0 = (linear & ~D::eq(qb, zero)) | (~linear & D::ge(disc, zero));
  const unsigned has1 = ~linear & D::ge(disc, zero) & ~D::eq(qq, zero);
  auto on_grid = [&](V r, unsigned has, V& x) {
    const V x24 = D::mul(r, D::set1(0x1p24));
    const unsigned inside = has & D::ge(x24, D::set1(1.0)) & D::ge(D::set1(0x1p24 - 1), x24);
    x = D::mul(D::floor_nonneg(D::add(x24, D::set1(0.5))), D::set1(0x1p-24));
    return inside;
  };
  V x0, x1;
  const unsigned in0 = on_grid(r0, has0, x0), in1 = on_grid(r1, has1, x1);
  const unsigned both = in0 & in1 & ~D::eq(x0, x1);
  const unsigned swap = D::gt(x0, x1);
  m0 = D::select(both, D::select(swap, x1, x0), D::select(in0, x0, D::select(in1, x1, D::set1(0.5))));
  m1 = D::select(swap, x0, x1);
  return both;
}

/// LaneKernels::fast_tests: fast_roots of geometry/ccd_fast.h per lane. A cubic with exactly
/// one sign change on [0, 1]: fast_root there. Otherwise (its ends certainly nonzero) [0, 1]
/// split at the estimated critical points (split_at at one, restrict_to for three parts at
/// two), the parts taken earliest first: one of one sign skipped, one with one sign change
/// to fast_root (a miss goes on to the next part), one that would need halving left open;
/// every part passed: no contact. Each lane follows the scalar code's steps with its
/// operations; a lane leaves a loop or a branch by a mask where the scalar code would have
/// left it, and a time that needs bisection is left open.
template <bool VF>
void fast_tests_of(const double* x0, const double* x1, const std::uint32_t (*ids)[4], std::size_t n,
                   std::uint8_t* decided, double* toi_out) {
  using D = DOps;
  using V = typename D::V;
  constexpr unsigned W = D::kLanes;
  constexpr unsigned kAll = (1u << W) - 1;
  const V zero = D::zero(), one = D::set1(1.0);
  alignas(64) double toi_lanes[W];
  for (std::size_t first = 0; first < n; first += W) {
    const unsigned m = static_cast<unsigned>(n - first < W ? n - first : W);
    LanePoints pts;
    gather(x0, x1, ids + first, m, pts);
    LaneCubic q;
    cubic_lanes<VF>(pts, q);
    const V ef = q.ef;
    const unsigned lanes = in_range(q) & ((1u << m) - 1) & kAll;
    const unsigned direct = one_sign_change_lanes(q.f, ef) & lanes;
    // fast_roots' split: the ends certainly nonzero, not one sign change on [0, 1]
    const unsigned split = lanes & ~direct & D::gt(D::abs(q.f[0]), ef) & D::gt(D::abs(q.f[3]), ef);
    unsigned hit = 0, miss = 0;
    V toi = zero;
    if (direct | split) {
      LaneInside in;
      inside_lanes<VF>(pts, q, in);
      V part[3][4], lo[3], hi[3];
      unsigned three_parts = 0, one_sign[3] = {0, 0, 0}, change[3] = {0, 0, 0};
      if (split) {
        V m0, m1;
        three_parts = split_points_lanes(q.f, m0, m1);
        // the parts' coefficients: split_at(f, ef, m0) where one point, restrict_to where two;
        // both grow the bound to ef + 12 u max|c| + 2^-800
        const V mag = D::max(D::max(D::max(D::max(zero, D::abs(q.f[0])), D::abs(q.f[1])), D::abs(q.f[2])), D::abs(q.f[3]));
        const V e = D::add(D::add(ef, D::mul(D::set1(12 * 0x1p-53), mag)), D::set1(0x1p-800));
        {
          const V s = m0, s1 = D::sub(one, s);  // split_at: de Casteljau at s
          V t[4] = {q.f[0], q.f[1], q.f[2], q.f[3]};
          V l[4], r[4];
          l[0] = t[0], r[3] = t[3];
          for (int k = 1; k <= 3; ++k) {
            for (int i = 0; i <= 3 - k; ++i) t[i] = D::add(D::mul(s1, t[i]), D::mul(s, t[i + 1]));
            l[k] = t[0], r[3 - k] = t[3 - k];
          }
          for (int k = 0; k < 4; ++k) part[0][k] = l[k], part[1][k] = r[k];
        }
        lo[0] = zero, hi[0] = m0, lo[1] = m0, hi[1] = D::select(three_parts, m1, one), lo[2] = m1, hi[2] = one;
        if (three_parts) {
          for (int j = 0; j < 3; ++j) {  // restrict_to(f, ef, lo, hi): the blossoms
            V rt[4];
            const V L = lo[j], H = hi[j], l1 = D::sub(one, L), h1 = D::sub(one, H);
            V row[4] = {q.f[0], q.f[1], q.f[2], q.f[3]};
            for (int c = 0; c <= 3; ++c) {
              V tmp[4];
              for (int i = 0; i <= 3 - c; ++i) tmp[i] = row[i];
              for (int level = 0; level < 3 - c; ++level)
                for (int i = 0; i < 3 - c - level; ++i) tmp[i] = D::add(D::mul(l1, tmp[i]), D::mul(L, tmp[i + 1]));
              rt[c] = tmp[0];
              for (int i = 0; i < 3 - c; ++i) row[i] = D::add(D::mul(h1, row[i]), D::mul(H, row[i + 1]));
            }
            for (int c = 0; c < 4; ++c) part[j][c] = j < 2 ? D::select(three_parts, rt[c], part[j][c]) : rt[c];
          }
        }
        for (int j = 0; j < 3; ++j) {
          const unsigned here = split & (j < 2 ? kAll : three_parts);
          one_sign[j] = definite_lanes(part[j], e) & here;
          change[j] = one_sign_change_lanes(part[j], e) & here & ~one_sign[j];
        }
      }
      // Rounds of fast_root, each on every lane's next piece at once: [0, 1] for the direct
      // lanes (decided in the first round); for a split lane, its parts earliest first, one of
      // one sign skipped, one that would need halving ending the lane (open), one with one sign
      // change taken (a miss there goes on to the next part); every part passed: no contact.
      unsigned at[3] = {split, 0, 0}, round_direct = direct;
      for (;;) {
        unsigned ready[3];
        for (int j = 0; j < 3; ++j) {
          const unsigned exists = j < 2 ? kAll : three_parts, passed = at[j] & ~exists;
          const unsigned skip = at[j] & exists & one_sign[j];
          ready[j] = at[j] & exists & change[j];
          miss |= passed | (j < 2 ? 0u : skip);
          if (j < 2) at[j + 1] |= skip;
          at[j] = 0;
        }
        const unsigned live = round_direct | ready[0] | ready[1] | ready[2];
        if (!live) break;
        V p[4], x = zero, y = one;
        for (int k = 0; k < 4; ++k) p[k] = q.f[k];
        for (int j = 0; j < 3; ++j) {
          if (!ready[j]) continue;
          for (int k = 0; k < 4; ++k) p[k] = D::select(ready[j], part[j][k], p[k]);
          x = D::select(ready[j], lo[j], x);
          y = D::select(ready[j], hi[j], y);
        }
        const RootLanes r = fast_root_lanes<VF>(q, in, p, x, y, live);
        hit |= r.hit;
        toi = D::select(r.hit, r.toi, toi);
        miss |= round_direct & r.miss;
        round_direct = 0;
        at[1] |= ready[0] & r.miss;
        at[2] |= ready[1] & r.miss;
        miss |= ready[2] & r.miss;
      }
    }
    D::store(toi_lanes, toi);
    for (unsigned i = 0; i < m; ++i) {
      const bool h = hit >> i & 1u;
      decided[first + i] = h ? kFastHit : (miss >> i & 1u) ? kFastMiss : kFastOpen;
      if (h) toi_out[first + i] = toi_lanes[i];
    }
  }
}

void fast_tests(bool vertex_face, const double* x0, const double* x1, const std::uint32_t (*ids)[4], std::size_t n,
                std::uint8_t* decided, double* toi) {
  if (vertex_face)
    fast_tests_of<true>(x0, x1, ids, n, decided, toi);
  else
    fast_tests_of<false>(x0, x1, ids, n, decided, toi);
}

/// The corners of up to W triangles (corners[0..m), the rest repeating the first) at t = 0 and
/// t = 1.
inline void gather_triangles(const double* x0, const double* x1, const std::uint32_t (*corners)[3], unsigned m,
                             P3 (&p)[2][3]) {
  gather_points<3>(x0, x1, corners, m, p);
}

/// LaneKernels::star_signs: core/self_culling.cpp's star_sign (with its split at t = 1/2), a
/// triangle per lane, its operations in its order (Eigen's componentwise differences and sums,
/// its cross and dot).
void star_signs(const double* x0, const double* x1, const std::uint32_t (*corners)[3], std::size_t n, const double* m0,
                const double* m1, double bound, double tiny, std::int8_t* signs) {
  using D = DOps;
  constexpr unsigned W = D::kLanes;
  const P3 c0{D::set1(m0[0]), D::set1(m0[1]), D::set1(m0[2])}, c1{D::set1(m1[0]), D::set1(m1[1]), D::set1(m1[2])};
  auto max_norm = [](const P3& v) { return D::max(D::max(D::abs(v.x), D::abs(v.y)), D::abs(v.z)); };
  const D::V k18 = D::set1(18), kb = D::set1(bound), knb = D::set1(-bound), kt = D::set1(tiny);
  for (std::size_t first = 0; first < n; first += W) {
    const unsigned m = static_cast<unsigned>(std::min<std::size_t>(W, n - first));
    P3 p[2][3];
    gather_triangles(x0, x1, corners + first, m, p);
    const P3 u0 = sub3(p[0][1], p[0][0]), u1 = sub3(p[1][1], p[1][0]), v0 = sub3(p[0][2], p[0][0]),
             v1 = sub3(p[1][2], p[1][0]), w0 = sub3(c0, p[0][0]), w1 = sub3(c1, p[1][0]);
    const P3 n0 = cross3(u0, v0), n1 = cross3(u1, v1), nm = add3(cross3(u0, v1), cross3(u1, v0));
    const D::V d[4] = {dot3(n0, w0), D::add(dot3(nm, w0), dot3(n0, w1)), D::add(dot3(nm, w1), dot3(n1, w0)),
                       dot3(n1, w1)};
    // std::max(a, b) is a < b ? b : a, which select() gives exactly (also for equal values)
    auto max2 = [](D::V a, D::V b) { return D::select(D::gt(b, a), b, a); };
    const D::V scale = D::mul(D::mul(D::mul(k18, max2(max_norm(u0), max_norm(u1))), max2(max_norm(v0), max_norm(v1))),
                              max2(max_norm(w0), max_norm(w1)));
    const unsigned ok = D::gt(scale, kt);
    const D::V hi = D::mul(kb, scale), lo = D::mul(knb, scale);
    unsigned pos = ok, neg = ok;
    for (const D::V v : d) {
      pos &= D::gt(v, hi);
      neg &= D::gt(lo, v);
    }
    // The lanes whose ends share a certain sign but not all four coefficients: the cubic split
    // at t = 1/2, its five sums in star_sign's order of operations, each against its weight
    // times the bound.
    const unsigned ends_pos = ok & D::gt(d[0], hi) & D::gt(d[3], hi), ends_neg = ok & D::gt(lo, d[0]) & D::gt(lo, d[3]);
    if (const unsigned open = (ends_pos | ends_neg) & ~(pos | neg)) {
      const D::V k3 = D::set1(3), k4 = D::set1(4), k6 = D::set1(6);
      const D::V t0 = D::mul(k3, d[0]), t3 = D::mul(k3, d[3]), a12 = D::add(d[1], d[2]);
      const D::V l1 = D::add(t0, d[1]), l2 = D::add(l1, a12), mid = D::add(D::add(d[0], d[1]), D::add(d[2], d[3])),
                 r2 = D::add(a12, D::add(d[2], t3)), r1 = D::add(d[2], t3);
      const D::V s4 = D::mul(k4, scale), s6 = D::mul(k6, scale);
      const D::V halves[5][2] = {{l1, s4}, {l2, s6}, {mid, s4}, {r2, s6}, {r1, s4}};
      unsigned hp = ends_pos & open, hn = ends_neg & open;
      for (const auto& h : halves) {
        hp &= D::gt(h[0], D::mul(kb, h[1]));
        hn &= D::gt(D::mul(knb, h[1]), h[0]);
      }
      pos |= hp;
      neg |= hn;
    }
    for (unsigned i = 0; i < m; ++i) signs[first + i] = static_cast<std::int8_t>((pos >> i & 1u) - (neg >> i & 1u));
  }
}

/// LaneKernels::normal_signs: core/self_culling.cpp's normal_signs (every axis wanted), a
/// triangle per lane, its operations in its order (product_sign<true>, bernstein_sign).
/// Without `bits`, only the axes the triangles so far all share are looked at (the same
/// shared bits: an axis one triangle lacks is lost whatever the others have).
unsigned normal_signs(const double* x0, const double* x1, const std::uint32_t (*corners)[3], std::size_t n,
                      double bound, double tiny, std::uint8_t* bits) {
  using D = DOps;
  constexpr unsigned W = D::kLanes;
  const D::V kb = D::set1(bound), knb = D::set1(-bound), kt = D::set1(tiny);
  unsigned shared = 0x3F;  // the bits every triangle so far has
  for (std::size_t first = 0; first < n; first += W) {
    const unsigned m = static_cast<unsigned>(std::min<std::size_t>(W, n - first));
    P3 p[2][3];
    gather_triangles(x0, x1, corners + first, m, p);
    D::V u[2][3], v[2][3];  // b - a and c - a at t = 0, 1, by coordinate
    for (unsigned e = 0; e < 2; ++e) {
      const P3 ue = sub3(p[e][1], p[e][0]), ve = sub3(p[e][2], p[e][0]);
      u[e][0] = ue.x, u[e][1] = ue.y, u[e][2] = ue.z;
      v[e][0] = ve.x, v[e][1] = ve.y, v[e][2] = ve.z;
    }
    unsigned lane_bits[3][2];  // per axis: the lanes certainly positive, certainly negative
    for (int d = 0; d < 3; ++d) {
      // without the triangles' own bits, an axis no triangle so far shares is not looked at
      if (!bits && !(shared >> (2 * d) & 3u)) {
        lane_bits[d][0] = lane_bits[d][1] = 0;
        continue;
      }
      const int i = (d + 1) % 3, j = (d + 2) % 3;
      // product_sign<true>'s term: p - q, and |p| + |q| into the magnitude
      auto term = [&](const D::V* a, const D::V* b, D::V& mag) {
        const D::V p = D::mul(a[i], b[j]), q = D::mul(a[j], b[i]);
        mag = D::add(D::abs(p), D::abs(q));
        return D::sub(p, q);
      };
      D::V e0, e1a, e1b, e2;
      const D::V c0 = term(u[0], v[0], e0);
      const D::V c1 = D::add(term(u[0], v[1], e1a), term(u[1], v[0], e1b));
      const D::V c2 = term(u[1], v[1], e2);
      const D::V e1 = D::add(e1a, e1b);
      const D::V cs[3] = {c0, c1, c2}, es[3] = {e0, e1, e2};
      unsigned pos = ~0u, neg = ~0u, normal = ~0u;
      for (int k = 0; k < 3; ++k) {
        pos &= D::gt(cs[k], D::mul(kb, es[k]));
        neg &= D::gt(D::mul(knb, es[k]), cs[k]);
        normal &= D::gt(es[k], kt);
      }
      lane_bits[d][0] = pos & normal;
      lane_bits[d][1] = neg & normal;
    }
    // the bits that every used lane has (the lanes past m repeat the first triangle)
    const unsigned used = (1u << m) - 1u;
    for (int d = 0; d < 3; ++d)
      for (int k = 0; k < 2; ++k)
        if ((lane_bits[d][k] & used) != used) shared &= ~(1u << (2 * d + k));
    if (!bits) {
      if (!shared) break;  // none left to share
      continue;
    }
    // A lane is never both certainly positive and certainly negative (with `normal`, each
    // magnitude is above `tiny`, so the two bounds have opposite signs): its bits are the two
    // masks' bits as they are, without a branch.
    for (unsigned l = 0; l < m; ++l) {
      unsigned b = 0;
      for (int d = 0; d < 3; ++d) b |= ((lane_bits[d][0] >> l & 1u) | (lane_bits[d][1] >> l & 1u) << 1) << (2 * d);
      bits[first + l] = static_cast<std::uint8_t>(b);
    }
  }
  return shared;
}

const LaneKernels kernels{&dops,       &pair_masks, &self_masks,   &merge_lanes,     &coplanar_quarters,
                          &fast_tests, &star_signs, &normal_signs, kVertexQuarters, kMergeQuarters,
                          Ops::kLevel};
