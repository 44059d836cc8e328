// LaneKernels::vertex_quarters over one instruction set, included by geometry/lane_masks.cpp
// in the namespaces of the sets that have it, after they define `VOps` (a vertex per lane):
//   kLanes                       vertices per register (4 or 8)
//   D, F, I                      kLanes doubles, floats, 32-bit integers
//   Offsets offsets(slots, m)    the offsets 3 v of the vertices slots[0, m), the lanes past
//                                m repeating the first
//   D gather(base, Offsets)      base[offset i] in lane i
//   (the double operations are DOps': set1, add, sub, mul, min, max, abs; min and max with the
//   SSE2 code's operand order, the second operand where both are zeros)
//   F cvt(D)                     to float, rounded to nearest
//   F fset(x), fsub, fmul, fmin, fmax
//   I cvtt(F), F fceil(F), I isub(I, I), I iset(x)
//   void istore(std::int32_t*, I)
//   void write_coarse(lower, upper, m, stored, CoarseDop* out)
//                                the free write_coarse's results (W = kLanes)
//   void store(const F lo[4], const F hi[4], unsigned m, unsigned stored, float* out)
//                                quarters 0-3 of lanes i < m in `stored` to out + 72 i (lo at 0,
//                                hi at 4)
// No headers here: geometry/lane_masks.cpp includes them before any instruction-set region.

/// LaneKernels::vertex_quarters: SweptVolumes::vertex_volumes's operations on kLanes vertices
/// at a time (its SSE2 path holds two slabs a register, this a vertex a lane), and
/// CoarseGrid::quantize's on the merge of the quarters (QuarterDop::whole's order).
void vertex_quarters(const double* x0, const double* x1, const std::uint32_t* vertex_of_slot, std::size_t n,
                     double min_distance, std::uint64_t skip, float* out, const CoarseOut* coarse) {
  using V = VOps;
  constexpr unsigned W = V::kLanes;
  const typename V::D quarter = DOps::set1(0.25), half = DOps::set1(0.5), three = DOps::set1(0.75);
  const typename V::D distance = DOps::set1(min_distance);
  // quarter_volumes.h's quarter_margin, its operations in its order
  const typename V::D relative = DOps::set1(kQuarterRelative), least = DOps::set1(kQuarterLeast);
  const typename V::D inflated = DOps::add(distance, DOps::mul(distance, relative));
  const typename V::D no_clamp = DOps::set1(kQuarterNoClamp);
  const typename V::F big = V::fset(std::numeric_limits<float>::max());
  const typename V::F low = V::fset(-std::numeric_limits<float>::max());
  const typename V::F zero = V::fset(0.0f), top = V::fset(65535.0f);
  const typename V::I middle = V::iset(32768);
  alignas(32) std::int32_t lower[9][W], upper[9][W];
  for (std::size_t g = 0; g < n; g += W) {
    const unsigned m = n - g >= W ? W : static_cast<unsigned>(n - g);
    const unsigned stored = ~static_cast<unsigned>(skip >> g) & ((1u << m) - 1u);
    if (!stored) continue;  // every one kept (a static mesh's vertices): nothing to compute
    const typename V::Offsets at = V::offsets(vertex_of_slot + g, m);
    const typename V::D ax = V::gather(x0, at), ay = V::gather(x0 + 1, at), az = V::gather(x0 + 2, at);
    const typename V::D bx = V::gather(x1, at), by = V::gather(x1 + 1, at), bz = V::gather(x1 + 2, at);
    // kdop.h's projections: x, y, z, x + y, x - y, x + z, x - z, y + z, y - z
    const typename V::D pa[9] = {ax, ay, az, DOps::add(ax, ay), DOps::sub(ax, ay), DOps::add(ax, az),
                                 DOps::sub(ax, az), DOps::add(ay, az), DOps::sub(ay, az)};
    const typename V::D pb[9] = {bx, by, bz, DOps::add(bx, by), DOps::sub(bx, by), DOps::add(bx, bz),
                                 DOps::sub(bx, bz), DOps::add(by, bz), DOps::sub(by, bz)};
    // the largest coordinate (a maximum: exact in any order), then the margin
    const typename V::D largest = DOps::max(DOps::max(DOps::max(DOps::abs(ax), DOps::abs(ay)), DOps::abs(az)),
                                          DOps::max(DOps::max(DOps::abs(bx), DOps::abs(by)), DOps::abs(bz)));
    const typename V::D margin = DOps::add(DOps::add(DOps::mul(largest, relative), inflated), least);
    // The bounds' overflow past the float range clamped only where a lane's coordinates come near
    // it (bit for bit the same: below kQuarterNoClamp every bound is a finite float already).
    const bool clamp = DOps::gt(largest, no_clamp) != 0;
    for (int s = 0; s < 9; ++s) {
      const typename V::D p0 = pa[s], p4 = pb[s], d = DOps::sub(p4, p0);
      const typename V::D p[5] = {p0, DOps::add(p0, DOps::mul(quarter, d)), DOps::add(p0, DOps::mul(half, d)),
                                  DOps::add(p0, DOps::mul(three, d)), p4};
      typename V::F lo[4], hi[4];
      for (int k = 0; k < 4; ++k) {
        lo[k] = V::cvt(DOps::sub(DOps::min(p[k], p[k + 1]), margin));
        hi[k] = V::cvt(DOps::add(DOps::max(p[k], p[k + 1]), margin));
      }
      if (clamp)
        for (int k = 0; k < 4; ++k) lo[k] = V::fmin(lo[k], big), hi[k] = V::fmax(hi[k], low);
      if (coarse) {  // the merge of the quarters, on the grid
        const typename V::F whole_lo = V::fmin(lo[3], V::fmin(lo[2], V::fmin(lo[1], lo[0])));
        const typename V::F whole_hi = V::fmax(hi[3], V::fmax(hi[2], V::fmax(hi[1], hi[0])));
        const typename V::F o = V::fset(coarse->origin[s]), k = V::fset(coarse->scale[s]);
        const typename V::F ql = V::fmin(V::fmax(V::fmul(V::fsub(whole_lo, o), k), zero), top);
        V::istore(lower[s], V::isub(V::cvtt(ql), middle));
        const typename V::F qh = V::fmax(V::fmin(V::fmul(V::fsub(whole_hi, o), k), top), zero);
        V::istore(upper[s], V::isub(V::cvtt(V::fceil(qh)), middle));  // qh is in [0, 65535]: exact
      }
      V::store(lo, hi, m, stored, out + 72 * g + 8 * s);
    }
    if (coarse) V::write_coarse(lower, upper, m, stored, coarse->out + g);
  }
}
