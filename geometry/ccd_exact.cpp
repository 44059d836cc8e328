// Exact instant contact predicates for the elementary CCD tests; see ccd_exact.h.
//
// Arithmetic: floating-point expansions (J. R. Shewchuk, "Adaptive precision floating-point
// arithmetic and fast robust geometric predicates", 1997). A value is an unevaluated sum of
// doubles, nonoverlapping, in increasing magnitude, without zeros; two-sum and two-product
// (with fma) are error-free as long as nothing overflows or underflows. The inputs are
// restricted to nonzero magnitudes in [2^-120, 2^120]: every term of a product of at most
// four coordinate differences then stays far inside the normal range (>= 2^-800, <= 2^500),
// so every operation below is exact and the signs are the exact signs.
#include <mccd/geometry/ccd_exact.h>

#include <cmath>

namespace mccd::detail {
namespace {

constexpr int kCap = 32;

struct Exp {
  int n = 0;
  double v[kCap];
  bool ok = true;  // false: capacity exceeded (the value is then unusable)
};

inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}
inline void fast_two_sum(double a, double b, double& x, double& y) {  // |a| >= |b| or a == 0
  x = a + b;
  y = b - (x - a);
}
inline void two_prod(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

inline void push(Exp& h, double x) {
  if (x == 0) return;
  if (h.n >= kCap) {
    h.ok = false;
    return;
  }
  h.v[h.n++] = x;
}

// Grow-Expansion with zero elimination (Shewchuk): h (n terms) += q, in place (each term is
// read before its slot is written); h has room for one more term.
inline void grow(double* h, int& n, double q) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    double s, t;
    two_sum(q, h[i], s, t);
    if (t != 0) h[m++] = t;
    q = s;
  }
  if (q != 0) h[m++] = q;
  n = m;
}

// h = e + f: grow() once per term of f, in one scratch buffer.
Exp sum(const Exp& e, const Exp& f) {
  Exp h;
  h.ok = e.ok && f.ok;
  if (!h.ok) return h;
  double buf[2 * kCap + 2];
  int n = e.n;
  for (int i = 0; i < n; ++i) buf[i] = e.v[i];
  for (int j = 0; j < f.n; ++j) {
    grow(buf, n, f.v[j]);
    if (n > 2 * kCap) {
      h.ok = false;
      return h;
    }
  }
  if (n > kCap) {
    h.ok = false;
    return h;
  }
  for (int i = 0; i < n; ++i) h.v[i] = buf[i];
  h.n = n;
  return h;
}

Exp neg(Exp e) {
  for (int i = 0; i < e.n; ++i) e.v[i] = -e.v[i];
  return e;
}

// Shewchuk's Compress: the same value with as few terms as possible.
Exp compress(const Exp& e) {
  if (e.n <= 1 || !e.ok) return e;
  double g[kCap];
  int bottom = e.n - 1;
  double q = e.v[bottom];
  for (int i = e.n - 2; i >= 0; --i) {
    double s, t;
    fast_two_sum(q, e.v[i], s, t);
    if (t != 0) {
      g[bottom--] = s;
      q = t;
    } else {
      q = s;
    }
  }
  g[bottom] = q;
  Exp h;
  double acc = g[bottom];
  for (int i = bottom + 1; i < e.n; ++i) {
    double s, t;
    fast_two_sum(g[i], acc, s, t);
    push(h, t);
    acc = s;
  }
  push(h, acc);
  return h;
}

// h = e * b (Scale-Expansion with zero elimination).
Exp scale(const Exp& e, double b) {
  Exp h;
  h.ok = e.ok;
  if (e.n == 0 || b == 0) return h;
  double q, t;
  two_prod(e.v[0], b, q, t);
  push(h, t);
  for (int i = 1; i < e.n; ++i) {
    double p1, p0, s, hh;
    two_prod(e.v[i], b, p1, p0);
    two_sum(q, p0, s, hh);
    push(h, hh);
    fast_two_sum(p1, s, q, hh);
    push(h, hh);
  }
  push(h, q);
  return h;
}

Exp mul(const Exp& e, const Exp& f) {
  Exp h;
  h.ok = e.ok && f.ok;
  for (int i = 0; i < f.n && h.ok; ++i) h = compress(sum(h, scale(e, f.v[i])));
  return h;
}

inline int sign(const Exp& e) { return e.n == 0 ? 0 : (e.v[e.n - 1] > 0 ? 1 : -1); }

// a - b, exactly (two terms at most).
Exp diff(double a, double b) {
  Exp h;
  double x, y;
  two_sum(a, -b, x, y);
  push(h, y);
  push(h, x);
  return h;
}

struct V3E {
  Exp x, y, z;
};

V3E vdiff(const Vec3& a, const Vec3& b) { return {diff(a.x(), b.x()), diff(a.y(), b.y()), diff(a.z(), b.z())}; }
Exp sub_mul(const Exp& a, const Exp& b, const Exp& c, const Exp& d) {  // a b - c d
  return compress(sum(mul(a, b), neg(mul(c, d))));
}
V3E vcross(const V3E& a, const V3E& b) {
  return {sub_mul(a.y, b.z, a.z, b.y), sub_mul(a.z, b.x, a.x, b.z), sub_mul(a.x, b.y, a.y, b.x)};
}
V3E vadd(const V3E& a, const V3E& b) {
  return {compress(sum(a.x, b.x)), compress(sum(a.y, b.y)), compress(sum(a.z, b.z))};
}
Exp vdot(const V3E& a, const V3E& b) { return compress(sum(sum(mul(a.x, b.x), mul(a.y, b.y)), mul(a.z, b.z))); }
bool all_ok(const V3E& a) { return a.x.ok && a.y.ok && a.z.ok; }
bool is_zero(const V3E& a) { return a.x.n == 0 && a.y.n == 0 && a.z.n == 0; }

// Every coordinate is zero or of magnitude in [2^-120, 2^120] (see the header comment).
bool in_range(const Vec3* p, int n) {
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      const double a = std::fabs(p[i][k]);
      if (a != 0 && !(a >= 0x1p-120 && a <= 0x1p120)) return false;
    }
  return true;
}

// ---- Floating-point filters ---------------------------------------------------------------
// A value computed in double from the input coordinates with at most k rounding levels along
// any path differs from the exact one by at most gamma_k * M, M the same expression on
// absolute values (coordinates in range, so no underflow beyond the 2^-900 term). We use
// 16 u for the degree-3 expressions (k <= 7) and 32 u for the degree-4 ones (k <= 10), both
// over gamma_k with room for the rounding of M itself. filt() returns the certain sign, or 2.
struct D3 {
  double x, y, z;
};
inline D3 dsub(const Vec3& a, const Vec3& b) { return {a.x() - b.x(), a.y() - b.y(), a.z() - b.z()}; }
inline D3 dabs(D3 a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
inline D3 dcross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline D3 dacross(D3 a, D3 b) { return {a.y * b.z + a.z * b.y, a.z * b.x + a.x * b.z, a.x * b.y + a.y * b.x}; }
inline D3 dadd(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline double ddot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr double kU = 0x1p-53;
inline int filt(double v, double mag, double k) {
  const double err = k * kU * mag + 0x1p-900;
  return v > err ? 1 : (v < -err ? -1 : 2);
}

}  // namespace

namespace {
// det(b - a, c - a, d - a) = sum of the six terms e_ijk (b - a)_i (c - a)_j (d - a)_k in plain
// double arithmetic, when that is exact: a term with a zero difference is exactly zero (a
// difference of two doubles rounds to zero only when they are equal); every other term needs
// its three differences exact and its two products exact, and the sum must be exact (each
// two_sum / two_prod error term zero). Then the result is the exact value, as for points on
// coarse grids, or points that share a coordinate (a cloth folded about an axis: every term
// vanishes). False when some needed operation rounded. With the coordinates in range (no
// underflow of products), the error terms themselves are exact.
bool orient3d_if_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double& det) {
  const Vec3* rows[3] = {&b, &c, &d};
  double v[3][3];
  bool ok[3][3];
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) {
      double e;
      two_sum((*rows[r])[k], -a[k], v[r][k], e);
      ok[r][k] = e == 0;
    }
  static constexpr int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
  double acc = 0;
  for (int t = 0; t < 6; ++t) {
    const int i = kPerm[t][0], j = kPerm[t][1], k = kPerm[t][2];
    const double x = v[0][i], y = v[1][j], z = v[2][k];
    if (x == 0 || y == 0 || z == 0) continue;
    if (!(ok[0][i] && ok[1][j] && ok[2][k])) return false;
    double p, q, e1, e2, s, e3;
    two_prod(x, y, p, e1);
    two_prod(p, z, q, e2);
    two_sum(acc, t < 3 ? q : -q, s, e3);
    if (e1 != 0 || e2 != 0 || e3 != 0) return false;
    acc = s;
  }
  det = acc;
  return true;
}

// det(b - a, c - a, d - a) exactly when the nine differences are exact doubles (two points
// closer than a factor 2 in a coordinate subtract exactly: nearby points of a mesh mostly do):
// each 2x2 minor of c - a and d - a as two two-products (an expansion of at most 4 terms),
// scaled by a component of b - a (at most 8), the three summed (at most 24); fixed arrays,
// no copies. Returns the sign, or 2 when some difference is inexact (the general path then).
int orient3d_exact_differences(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  double B[3], C[3], D[3];
  const Vec3* rows[3] = {&b, &c, &d};
  double* out[3] = {B, C, D};
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) {
      double e;
      two_sum((*rows[r])[k], -a[k], out[r][k], e);
      if (e != 0) return 2;
    }
  double det[24];
  int nd = 0;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    if (B[i] == 0) continue;
    // the minor C_j D_k - C_k D_j
    double minor[4];
    int nm = 0;
    double p1, p0, q1, q0;
    two_prod(C[j], D[k], p1, p0);
    two_prod(C[k], D[j], q1, q0);
    grow(minor, nm, p0);
    grow(minor, nm, p1);
    grow(minor, nm, -q0);
    grow(minor, nm, -q1);
    if (nm == 0) continue;
    // B_i times the minor (Scale-Expansion), each term added to det
    for (int t = 0; t < nm; ++t) {
      double x1, x0;
      two_prod(minor[t], B[i], x1, x0);
      grow(det, nd, x0);
      grow(det, nd, x1);
    }
  }
  return nd == 0 ? 0 : (det[nd - 1] > 0 ? 1 : -1);
}

}  // namespace

int exact_orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 pts[4] = {a, b, c, d};
  if (!in_range(pts, 4)) return 2;
  if (double det; orient3d_if_exact(a, b, c, d, det)) return det > 0 ? 1 : (det < 0 ? -1 : 0);
  if (const int s = orient3d_exact_differences(a, b, c, d); s != 2) return s;
  const V3E B = vdiff(b, a), C = vdiff(c, a), D = vdiff(d, a);
  const Exp det = vdot(B, vcross(C, D));
  if (!det.ok) return 2;
  return sign(det);
}

bool exact_vertex_face_touch(const std::array<Vec3, 4>& pts) {
  const Vec3 &p = pts[0], &a = pts[1], &b = pts[2], &c = pts[3];
  if (p == a || p == b || p == c) return p.allFinite();
  if (!in_range(pts.data(), 4)) return false;
  // Filter: the coplanarity determinant and the barycentric functions in double.
  const D3 dA = dsub(a, p), dB = dsub(b, p), dC = dsub(c, p);
  const D3 mA = dabs(dA), mB = dabs(dB), mC = dabs(dC);
  const D3 dX = dcross(dB, dC), dY = dcross(dC, dA), dZ = dcross(dA, dB);
  const D3 mX = dacross(mB, mC), mY = dacross(mC, mA), mZ = dacross(mA, mB);
  if (filt(ddot(dA, dX), ddot(mA, mX), 16) != 2) return false;  // certainly not coplanar
  const D3 dn = dadd(dadd(dX, dY), dZ), mn = dadd(dadd(mX, mY), mZ);
  const int s0 = filt(ddot(dn, dX), ddot(mn, mX), 32), s1 = filt(ddot(dn, dY), ddot(mn, mY), 32),
            s2 = filt(ddot(dn, dZ), ddot(mn, mZ), 32);
  if (s0 == -1 || s1 == -1 || s2 == -1) return false;  // certainly outside
  // Exact: the determinant, then the barycentric functions unless all certainly positive.
  const V3E A = vdiff(a, p), B = vdiff(b, p), C = vdiff(c, p);
  const V3E X = vcross(B, C), Y = vcross(C, A), Z = vcross(A, B);
  const Exp f = vdot(A, X);
  if (!f.ok || sign(f) != 0) return false;
  if (s0 == 1 && s1 == 1 && s2 == 1) return true;  // n != 0 since n.X > 0
  // n = (b - a) x (c - a) = X + Y + Z; at a coplanar p, n.X, n.Y, n.Z are the barycentric
  // coordinates of p times |n|^2.
  const V3E n = vadd(vadd(X, Y), Z);
  if (!all_ok(n) || is_zero(n)) return false;
  for (const V3E* g : {&X, &Y, &Z}) {
    const Exp s = vdot(n, *g);
    if (!s.ok || sign(s) < 0) return false;
  }
  return true;
}

bool exact_edge_edge_touch(const std::array<Vec3, 4>& pts) {
  const Vec3 &a0 = pts[0], &a1 = pts[1], &b0 = pts[2], &b1 = pts[3];
  if (a0 == b0 || a0 == b1 || a1 == b0 || a1 == b1) return a0.allFinite() && a1.allFinite();
  if (!in_range(pts.data(), 4)) return false;
  // Filter in double: coplanarity, then the segment parameters (s, 1 - s, r, 1 - r) |e|^2.
  int sg[4] = {2, 2, 2, 2};
  {
    const D3 dda = dsub(a1, a0), ddb = dsub(b1, b0), dw = dsub(b0, a0);
    const D3 mda = dabs(dda), mdb = dabs(ddb), mw = dabs(dw);
    const D3 de = dcross(dda, ddb), me = dacross(mda, mdb);
    if (filt(ddot(dw, de), ddot(mw, me), 16) != 2) return false;
    const double ee = ddot(de, de), mee = ddot(me, me);
    const double sn = ddot(dcross(dw, ddb), de), ms = ddot(dacross(mw, mdb), me);
    const double rn = ddot(dcross(dw, dda), de), mr = ddot(dacross(mw, mda), me);
    sg[0] = filt(sn, ms, 32), sg[1] = filt(ee - sn, mee + ms, 40);
    sg[2] = filt(rn, mr, 32), sg[3] = filt(ee - rn, mee + mr, 40);
    for (const int g : sg)
      if (g == -1) return false;
  }
  const V3E da = vdiff(a1, a0), db = vdiff(b1, b0), w = vdiff(b0, a0);
  const V3E e = vcross(da, db);
  if (!all_ok(e) || is_zero(e)) return false;  // parallel (or degenerate) edges: not decided
  const Exp f = vdot(w, e);
  if (!f.ok || sign(f) != 0) return false;
  // a0 + s da = b0 + r db with s = (w x db).e / |e|^2 and r = (w x da).e / |e|^2.
  if (sg[0] == 1 && sg[1] == 1 && sg[2] == 1 && sg[3] == 1) return true;
  const Exp ee = vdot(e, e);
  const Exp s = vdot(vcross(w, db), e);
  const Exp r = vdot(vcross(w, da), e);
  if (!ee.ok || !s.ok || !r.ok) return false;
  if (sign(s) < 0 || sign(r) < 0) return false;
  const Exp s1 = compress(sum(ee, neg(s))), r1 = compress(sum(ee, neg(r)));
  if (!s1.ok || !r1.ok) return false;
  return sign(s1) >= 0 && sign(r1) >= 0;
}

}  // namespace mccd::detail
