#pragma once
/// @file Exact reference for the elementary CCD tests, with GMP rationals (tests only).
///
/// Decides exactly whether a vertex-face or edge-edge query with double inputs touches at
/// some t in [0, 1], and gives the earliest time of contact as an isolating interval of a
/// real algebraic number. Method:
///  - the coplanarity polynomial f(t) (cubic) is computed exactly;
///  - if f is not identically zero, contact times are among its real roots in [0, 1]: they
///    are isolated exactly (square-free part, Sturm sequences, rational bisection) and at
///    each root the inside conditions are decided by the exact sign of polynomials at an
///    algebraic number (gcd test for zero, then refinement until the sign is fixed). A
///    degenerate face or parallel edges at the root reduce to point-on-segment tests;
///  - if f is identically zero (coplanar motion), the first contact is at t = 0 or a
///    vertex-edge contact (VF: p against the three edges; EE: each end against the other
///    edge), each decided exactly the same way.
#include <gmpxx.h>

#include <vector>

#include <mccd/geometry/ccd.h>

namespace mccd::test {

/// A polynomial in t with rational coefficients, c[i] t^i.
struct QPoly {
  std::vector<mpq_class> c;
};

/// A real number in [0, 1]: exact (`is_exact`, value `lo` == `hi`), or the only root of the
/// square-free `poly` in the open interval (lo, hi), with poly(lo), poly(hi) of opposite signs.
struct AlgebraicTime {
  bool is_exact = true;
  mpq_class lo, hi;
  QPoly poly;
};

struct ExactResult {
  bool hit = false;
  AlgebraicTime toi;  ///< earliest contact time (when hit)
};

ExactResult exact_vertex_face(const CcdPoints& p);
ExactResult exact_edge_edge(const CcdPoints& p);

/// Whether x <= t exactly.
bool time_not_after(double x, const AlgebraicTime& t);

}  // namespace mccd::test
