#include <mccd/geometry/ccd_filter.h>

#include <mccd/geometry/ccd_stages.h>

namespace mccd::detail {

unsigned coplanar_quarters(CcdKind kind, const CcdPoints& p, double min_distance) {
  Setup<double> S;
  S.kind = kind;
  if (load(p, min_distance > 0 ? min_distance : 0.0, S) != Load::Ok) return 0xF;
  coplanarity(S);
  // A definite sign of every Bernstein coefficient beyond the error bound (plus the distance
  // margin) proves the cubic nonzero on the whole closed piece: the convex hull property.
  if (definite_sign(S.f, S.ef + S.dN) != 0) return 0;
  Bern<3, double> h[2], q[4];
  const double eh = split_half(S.f, S.ef, h[0], h[1]);
  unsigned mask = 0;
  for (int i = 0; i < 2; ++i) {
    if (definite_sign(h[i], eh + S.dN) != 0) continue;
    const double eq = split_half(h[i], eh, q[2 * i], q[2 * i + 1]);
    for (int j = 0; j < 2; ++j)
      if (definite_sign(q[2 * i + j], eq + S.dN) == 0) mask |= 1u << (2 * i + j);
  }
  return mask;
}

}  // namespace mccd::detail
