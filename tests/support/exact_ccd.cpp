// Exact CCD reference with GMP rationals (see exact_ccd.h).
#include "support/exact_ccd.h"

#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>

namespace mccd::test {
namespace {

using Q = mpq_class;

// ---- polynomials -------------------------------------------------------------------------

void trim(QPoly& p) {
  while (!p.c.empty() && sgn(p.c.back()) == 0) p.c.pop_back();
}
int degree(const QPoly& p) { return static_cast<int>(p.c.size()) - 1; }  // -1 for zero
bool is_zero(const QPoly& p) { return p.c.empty(); }

QPoly linear(const Q& a0, const Q& a1) {  // a0 (1-t) + a1 t
  QPoly p{{a0, a1 - a0}};
  trim(p);
  return p;
}
QPoly add(const QPoly& a, const QPoly& b) {
  QPoly r;
  r.c.resize(std::max(a.c.size(), b.c.size()));
  for (std::size_t i = 0; i < a.c.size(); ++i) r.c[i] += a.c[i];
  for (std::size_t i = 0; i < b.c.size(); ++i) r.c[i] += b.c[i];
  trim(r);
  return r;
}
QPoly neg(QPoly a) {
  for (Q& x : a.c) x = -x;
  return a;
}
QPoly sub(const QPoly& a, const QPoly& b) { return add(a, neg(b)); }
QPoly mul(const QPoly& a, const QPoly& b) {
  if (is_zero(a) || is_zero(b)) return {};
  QPoly r;
  r.c.assign(a.c.size() + b.c.size() - 1, Q(0));
  for (std::size_t i = 0; i < a.c.size(); ++i)
    for (std::size_t j = 0; j < b.c.size(); ++j) r.c[i + j] += a.c[i] * b.c[j];
  trim(r);
  return r;
}
Q eval(const QPoly& p, const Q& t) {
  Q r = 0;
  for (std::size_t i = p.c.size(); i-- > 0;) r = r * t + p.c[i];
  return r;
}
int sign_at(const QPoly& p, const Q& t) { return sgn(eval(p, t)); }
QPoly deriv(const QPoly& p) {
  QPoly r;
  for (std::size_t i = 1; i < p.c.size(); ++i) r.c.push_back(p.c[i] * static_cast<long>(i));
  trim(r);
  return r;
}
// Remainder of a / b (b nonzero).
QPoly rem(QPoly a, const QPoly& b) {
  const int db = degree(b);
  while (degree(a) >= db) {
    const Q f = a.c.back() / b.c.back();
    const int shift = degree(a) - db;
    for (int i = 0; i <= db; ++i) a.c[shift + i] -= f * b.c[i];
    a.c.pop_back();
    trim(a);
  }
  return a;
}
QPoly quot(QPoly a, const QPoly& b) {
  const int db = degree(b);
  QPoly q;
  if (degree(a) < db) return q;
  q.c.assign(degree(a) - db + 1, Q(0));
  while (degree(a) >= db) {
    const Q f = a.c.back() / b.c.back();
    const int shift = degree(a) - db;
    q.c[shift] = f;
    for (int i = 0; i <= db; ++i) a.c[shift + i] -= f * b.c[i];
    a.c.pop_back();
    trim(a);
  }
  trim(q);
  return q;
}
QPoly monic(QPoly p) {
  if (is_zero(p)) return p;
  const Q lead = p.c.back();
  for (Q& x : p.c) x /= lead;
  return p;
}
QPoly gcd(QPoly a, QPoly b) {
  while (!is_zero(b)) {
    QPoly r = rem(a, b);
    a = std::move(b);
    b = std::move(r);
  }
  return monic(a);
}
QPoly squarefree(const QPoly& p) {
  if (degree(p) <= 1) return monic(p);
  const QPoly g = gcd(p, deriv(p));
  return monic(quot(p, g));
}

// Sturm sequence of a square-free p.
std::vector<QPoly> sturm(const QPoly& p) {
  std::vector<QPoly> s{p, deriv(p)};
  while (!is_zero(s.back())) {
    QPoly r = neg(rem(s[s.size() - 2], s.back()));
    if (is_zero(r)) break;
    s.push_back(std::move(r));
  }
  if (is_zero(s.back())) s.pop_back();
  return s;
}
int variations(const std::vector<QPoly>& s, const Q& t) {
  int v = 0, last = 0;
  for (const QPoly& p : s) {
    const int sg = sign_at(p, t);
    if (sg == 0) continue;
    if (last != 0 && sg != last) ++v;
    last = sg;
  }
  return v;
}
// Number of distinct roots in (a, b].
int count_roots(const std::vector<QPoly>& s, const Q& a, const Q& b) { return variations(s, a) - variations(s, b); }

// Real roots of p (not identically zero) in [0, 1], ascending, as AlgebraicTime.
std::vector<AlgebraicTime> roots_in_unit(const QPoly& p_in) {
  std::vector<AlgebraicTime> out;
  if (degree(p_in) <= 0) return out;
  const QPoly p = squarefree(p_in);
  const std::vector<QPoly> st = sturm(p);
  auto exact = [&](const Q& v) {
    AlgebraicTime a;
    a.is_exact = true;
    a.lo = a.hi = v;
    return a;
  };
  if (sign_at(p, Q(0)) == 0) out.push_back(exact(Q(0)));
  // Isolate roots in (0, 1] by bisection on Sturm counts.
  struct Iv {
    Q a, b;
    int n;
  };
  std::vector<Iv> work{{Q(0), Q(1), count_roots(st, Q(0), Q(1))}};
  std::vector<Iv> single;
  while (!work.empty()) {
    Iv iv = work.back();
    work.pop_back();
    if (iv.n == 0) continue;
    if (iv.n == 1) {
      single.push_back(iv);
      continue;
    }
    Q m = (iv.a + iv.b) / 2;
    const int nl = count_roots(st, iv.a, m);
    work.push_back({m, iv.b, iv.n - nl});
    work.push_back({iv.a, m, nl});
  }
  std::sort(single.begin(), single.end(), [](const Iv& x, const Iv& y) { return x.a < y.a; });
  for (Iv iv : single) {
    // One root in (a, b]. Exact at b? Otherwise shrink until both ends are nonzero.
    if (sign_at(p, iv.b) == 0) {
      out.push_back(exact(iv.b));
      continue;
    }
    while (sign_at(p, iv.a) == 0) {
      const Q m = (iv.a + iv.b) / 2;
      if (sign_at(p, m) == 0) {
        // m is a root; is it ours? It lies in (a, b], and ours is the only one there.
        iv.a = iv.b = m;
        break;
      }
      if (count_roots(st, iv.a, m) == 1)
        iv.b = m;
      else
        iv.a = m;
    }
    if (iv.a == iv.b) {
      out.push_back(exact(iv.a));
      continue;
    }
    AlgebraicTime a;
    a.is_exact = false;
    a.lo = iv.a;
    a.hi = iv.b;
    a.poly = p;
    out.push_back(a);
  }
  return out;
}

// Halves the isolating interval once.
void refine(AlgebraicTime& t) {
  if (t.is_exact) return;
  const Q m = (t.lo + t.hi) / 2;
  const int sm = sign_at(t.poly, m);
  if (sm == 0) {
    t.is_exact = true;
    t.lo = t.hi = m;
    return;
  }
  if (sm == sign_at(t.poly, t.lo))
    t.lo = m;
  else
    t.hi = m;
}

// Exact sign of h at the algebraic time t.
int sign_at(const QPoly& h, AlgebraicTime t) {
  if (is_zero(h)) return 0;
  if (t.is_exact) return sign_at(h, t.lo);
  // Fast path: centred form. For t in [lo, hi] within [0, 1], |h(t) - h(m)| <= r sum i|c_i|
  // with r = (hi - lo) / 2; refine the interval a bounded number of times.
  Q lip = 0;
  for (std::size_t i = 1; i < h.c.size(); ++i) lip += abs(h.c[i]) * static_cast<long>(i);
  {
    AlgebraicTime u = t;
    for (int it = 0; it < 48; ++it) {
      if (u.is_exact) return sign_at(h, u.lo);
      const Q m = (u.lo + u.hi) / 2;
      const Q hm = eval(h, m);
      if (abs(hm) > (u.hi - u.lo) / 2 * lip) return sgn(hm);
      refine(u);
    }
    t = u;
  }
  const QPoly g = gcd(t.poly, h);
  if (degree(g) >= 1 && sign_at(g, t.lo) != sign_at(g, t.hi)) return 0;
  // h(t) != 0: refine until h has no root in [lo, hi].
  const QPoly hs = squarefree(h);
  const std::vector<QPoly> st = sturm(hs);
  while (true) {
    if (t.is_exact) return sign_at(h, t.lo);
    if (sign_at(hs, t.lo) != 0 && count_roots(st, t.lo, t.hi) == 0) return sign_at(h, t.hi);
    refine(t);
  }
}

// ---- geometry ----------------------------------------------------------------------------

using PV = std::array<QPoly, 3>;  // a point or vector moving linearly (degree <= 1 each)

PV moving(const Vec3& a, const Vec3& b) {
  return {linear(Q(a.x()), Q(b.x())), linear(Q(a.y()), Q(b.y())), linear(Q(a.z()), Q(b.z()))};
}
PV vsub(const PV& a, const PV& b) { return {sub(a[0], b[0]), sub(a[1], b[1]), sub(a[2], b[2])}; }
PV vcross(const PV& a, const PV& b) {
  return {sub(mul(a[1], b[2]), mul(a[2], b[1])), sub(mul(a[2], b[0]), mul(a[0], b[2])),
          sub(mul(a[0], b[1]), mul(a[1], b[0]))};
}
QPoly vdot(const PV& a, const PV& b) { return add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2])); }

// p on the closed segment [a, b] at time t.
bool on_segment_at(const PV& p, const PV& a, const PV& b, const AlgebraicTime& t) {
  const PV c = vcross(vsub(b, a), vsub(p, a));
  for (const QPoly& x : c)
    if (sign_at(x, t) != 0) return false;
  // Collinear: p between a and b iff (p - a).(p - b) <= 0 (covers a == b).
  return sign_at(vdot(vsub(p, a), vsub(p, b)), t) <= 0;
}

// Earliest time in [0, 1] at which p lies on segment [a, b], if any.
std::optional<AlgebraicTime> vertex_edge_earliest(const PV& p, const PV& a, const PV& b) {
  const PV c = vcross(vsub(b, a), vsub(p, a));
  const QPoly q = vdot(vsub(p, a), vsub(p, b));
  QPoly h;
  for (const QPoly& x : c)
    if (!is_zero(x)) h = is_zero(h) ? x : gcd(h, x);
  if (is_zero(h)) {
    // Collinear throughout: the earliest t with q(t) <= 0.
    if (sign_at(q, Q(0)) <= 0) {
      AlgebraicTime z;
      z.lo = z.hi = 0;
      return z;
    }
    if (is_zero(q)) return std::nullopt;  // unreachable (q(0) > 0)
    for (const AlgebraicTime& r : roots_in_unit(q)) return r;
    return std::nullopt;
  }
  if (degree(h) == 0) return std::nullopt;
  for (const AlgebraicTime& r : roots_in_unit(h))
    if (sign_at(q, r) <= 0) return r;
  return std::nullopt;
}

std::optional<AlgebraicTime> earliest(std::optional<AlgebraicTime> a, std::optional<AlgebraicTime> b) {
  if (!a) return b;
  if (!b) return a;
  // Compare exactly: refine until the intervals separate, or decide equality of exact values.
  AlgebraicTime x = *a, y = *b;
  for (int it = 0; it < 400; ++it) {
    if (x.is_exact && y.is_exact) return x.lo <= y.lo ? *a : *b;
    if (x.hi < y.lo || (x.hi == y.lo && (x.is_exact || !y.is_exact))) return *a;
    if (y.hi < x.lo || (y.hi == x.lo && y.is_exact)) return *b;
    // Equal algebraic numbers? common root test.
    if (!x.is_exact && !y.is_exact) {
      const QPoly g = gcd(x.poly, y.poly);
      const Q lo = std::max(x.lo, y.lo), hi = std::min(x.hi, y.hi);
      if (degree(g) >= 1 && lo < hi && sign_at(g, lo) != 0 && sign_at(g, hi) != 0 && sign_at(g, lo) != sign_at(g, hi))
        return *a;  // the same number
    }
    if (x.is_exact && !y.is_exact && sign_at(y.poly, x.lo) == 0) return *a;
    if (y.is_exact && !x.is_exact && sign_at(x.poly, y.lo) == 0) return *b;
    refine(x);
    refine(y);
  }
  throw std::logic_error("exact_ccd: cannot order two contact times");
}

// The polynomials of the inside tests, computed once per query.
struct VfPolys {
  PV p, a, b, c;
  QPoly nn, gx, gy, gz;
  VfPolys(const PV& p_, const PV& a_, const PV& b_, const PV& c_) : p(p_), a(a_), b(b_), c(c_) {
    const PV A = vsub(a, p), B = vsub(b, p), C = vsub(c, p);
    const PV X = vcross(B, C), Y = vcross(C, A), Z = vcross(A, B);
    const PV n = {add(add(X[0], Y[0]), Z[0]), add(add(X[1], Y[1]), Z[1]), add(add(X[2], Y[2]), Z[2])};
    nn = vdot(n, n), gx = vdot(n, X), gy = vdot(n, Y), gz = vdot(n, Z);
  }
};

bool vf_contact_at(const VfPolys& P, const AlgebraicTime& t) {
  if (sign_at(P.nn, t) > 0) return sign_at(P.gx, t) >= 0 && sign_at(P.gy, t) >= 0 && sign_at(P.gz, t) >= 0;
  return on_segment_at(P.p, P.a, P.b, t) || on_segment_at(P.p, P.b, P.c, t) || on_segment_at(P.p, P.c, P.a, t);
}

struct EePolys {
  PV a0, a1, b0, b1;
  QPoly ee, g1, g2, g3, g4;
  EePolys(const PV& a0_, const PV& a1_, const PV& b0_, const PV& b1_) : a0(a0_), a1(a1_), b0(b0_), b1(b1_) {
    const PV da = vsub(a1, a0), db = vsub(b1, b0), w = vsub(b0, a0);
    const PV e = vcross(da, db);
    ee = vdot(e, e), g1 = vdot(vcross(w, db), e), g3 = vdot(vcross(w, da), e);
    g2 = sub(ee, g1), g4 = sub(ee, g3);
  }
};

bool ee_contact_at(const EePolys& P, const AlgebraicTime& t) {
  if (sign_at(P.ee, t) > 0)
    return sign_at(P.g1, t) >= 0 && sign_at(P.g2, t) >= 0 && sign_at(P.g3, t) >= 0 && sign_at(P.g4, t) >= 0;
  return on_segment_at(P.a0, P.b0, P.b1, t) || on_segment_at(P.a1, P.b0, P.b1, t) || on_segment_at(P.b0, P.a0, P.a1, t) ||
         on_segment_at(P.b1, P.a0, P.a1, t);
}

AlgebraicTime zero_time() {
  AlgebraicTime z;
  z.lo = z.hi = 0;
  return z;
}

}  // namespace

// True when the cubic f (power basis) has Bernstein coefficients on [0, 1] all of one
// strict sign: then f has no root in [0, 1].
bool no_root_in_unit(const QPoly& f) {
  if (is_zero(f)) return false;
  std::vector<Q> c(4, Q(0));
  for (std::size_t i = 0; i < f.c.size() && i < 4; ++i) c[i] = f.c[i];
  if (f.c.size() > 4) return false;
  // b_k = sum_{i<=k} C(k,i)/C(3,i) c_i
  const Q b0 = c[0], b1 = c[0] + c[1] / 3, b2 = c[0] + c[1] * 2 / 3 + c[2] / 3, b3 = c[0] + c[1] + c[2] + c[3];
  const int s0 = sgn(b0);
  return s0 != 0 && sgn(b1) == s0 && sgn(b2) == s0 && sgn(b3) == s0;
}

ExactResult exact_vertex_face(const CcdPoints& q) {
  const PV p = moving(q.start[0], q.end[0]), a = moving(q.start[1], q.end[1]), b = moving(q.start[2], q.end[2]),
           c = moving(q.start[3], q.end[3]);
  const QPoly f = vdot(vsub(a, p), vcross(vsub(b, p), vsub(c, p)));
  ExactResult r;
  if (no_root_in_unit(f)) return r;
  const VfPolys P(p, a, b, c);
  if (!is_zero(f)) {
    for (const AlgebraicTime& t : roots_in_unit(f))
      if (vf_contact_at(P, t)) return {true, t};
    return r;
  }
  if (vf_contact_at(P, zero_time())) return {true, zero_time()};
  std::optional<AlgebraicTime> best =
      earliest(earliest(vertex_edge_earliest(p, a, b), vertex_edge_earliest(p, b, c)), vertex_edge_earliest(p, c, a));
  if (best) return {true, *best};
  return r;
}

ExactResult exact_edge_edge(const CcdPoints& q) {
  const PV a0 = moving(q.start[0], q.end[0]), a1 = moving(q.start[1], q.end[1]), b0 = moving(q.start[2], q.end[2]),
           b1 = moving(q.start[3], q.end[3]);
  const QPoly f = vdot(vsub(b0, a0), vcross(vsub(a1, a0), vsub(b1, b0)));
  ExactResult r;
  if (no_root_in_unit(f)) return r;
  const EePolys P(a0, a1, b0, b1);
  if (!is_zero(f)) {
    for (const AlgebraicTime& t : roots_in_unit(f))
      if (ee_contact_at(P, t)) return {true, t};
    return r;
  }
  if (ee_contact_at(P, zero_time())) return {true, zero_time()};
  std::optional<AlgebraicTime> best =
      earliest(earliest(vertex_edge_earliest(a0, b0, b1), vertex_edge_earliest(a1, b0, b1)),
               earliest(vertex_edge_earliest(b0, a0, a1), vertex_edge_earliest(b1, a0, a1)));
  if (best) return {true, *best};
  return r;
}

bool time_not_after(double x, const AlgebraicTime& t) {
  const Q v(x);
  if (t.is_exact) return v <= t.lo;
  if (v <= t.lo) return true;
  if (v >= t.hi) return false;
  // lo < v < hi: the root is >= v iff p(v) has the sign of p(lo) or is zero.
  const int sv = sign_at(t.poly, v);
  return sv == 0 || sv == sign_at(t.poly, t.lo);
}

}  // namespace mccd::test
