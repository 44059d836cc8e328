#include <mccd/geometry/ccd_filter.h>

#include <mccd/geometry/ccd_setup.h>

namespace mccd::detail {

unsigned coplanar_quarters(CcdKind kind, const CcdPoints& p, double min_distance, unsigned within) {
  Setup<double> S;
  S.kind = kind;
  if (load(p, min_distance > 0 ? min_distance : 0.0, S) != Load::Ok) return within;
  // The cubic f = a . (b x c) of ccd_stages.h coplanarity(), without what only stage (c)
  // needs: VF a = A, b = B, c = C (corners minus the vertex); EE a = w, b = da, c = db.
  using V = V3<double>;
  V a0, a1, b0, b1, c0, c1;
  if (kind == CcdKind::VertexFace) {
    a0 = S.s[1] - S.s[0], a1 = S.e[1] - S.e[0];
    b0 = S.s[2] - S.s[0], b1 = S.e[2] - S.e[0];
    c0 = S.s[3] - S.s[0], c1 = S.e[3] - S.e[0];
  } else {
    a0 = S.s[2] - S.s[0], a1 = S.e[2] - S.e[0];  // w
    b0 = S.s[1] - S.s[0], b1 = S.e[1] - S.e[0];  // da
    c0 = S.s[3] - S.s[2], c1 = S.e[3] - S.e[2];  // db
  }
  const double ma = std::max(amax(a0), amax(a1)), mb = std::max(amax(b0), amax(b1)), mc = std::max(amax(c0), amax(c1));
  const Bern<3, double> f = cubic(a0, a1, cross(b0, c0), cross(b0, c1) + cross(b1, c0), cross(b1, c1));
  // The same bounds as coplanarity(): 96 u times the product of the three magnitudes (9
  // roundings at most), and the distance margin d times a bound on the normal's length.
  const double ef = 96 * kU * (ma * mb * mc) + kTiny;
  double dN = 0;
  if (S.d > 0) dN = S.d * (kind == CcdKind::VertexFace ? 3 * (mb * mc + mc * ma + ma * mb) : 3 * mb * mc) * (1 + 16 * kU);
  // A definite sign of every Bernstein coefficient beyond the error bound (plus the distance
  // margin) proves the cubic nonzero on the whole closed piece: the convex hull property.
  if (definite_sign(f, ef + dN) != 0) return 0;
  Bern<3, double> h[2], q[4];
  const double eh = split_half(f, ef, h[0], h[1]);
  unsigned mask = 0;
  for (int i = 0; i < 2; ++i) {
    const unsigned half = within >> (2 * i) & 3u;
    if (!half || definite_sign(h[i], eh + dN) != 0) continue;
    const double eq = split_half(h[i], eh, q[2 * i], q[2 * i + 1]);
    for (int j = 0; j < 2; ++j)
      if ((half >> j & 1u) && definite_sign(q[2 * i + j], eq + dN) == 0) mask |= 1u << (2 * i + j);
  }
  return mask;
}

}  // namespace mccd::detail
