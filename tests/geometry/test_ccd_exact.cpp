// The exact instant predicates of the elementary CCD tests (geometry/ccd_exact.h), against
// GMP rationals: orient3d signs, and the touch certificates (true must mean touching; exact
// touches built on dyadic grids must be certified; one-ulp perturbations must not be).
#include <mccd/geometry/ccd_exact.h>

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include <mccd/geometry/query_io.h>
#include "support/data.h"
#include "support/exact_ccd.h"

using namespace mccd;
namespace fs = std::filesystem;

namespace {

int gmp_orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  mpq_class m[3][3];
  const Vec3* p[3] = {&b, &c, &d};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) m[i][k] = mpq_class((*p[i])[k]) - mpq_class(a[k]);
  const mpq_class det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                        m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                        m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return sgn(det);
}

// A static query (start == end): the GMP reference then decides touching at that instant.
bool gmp_touch(bool vf, const std::array<Vec3, 4>& x) {
  CcdPoints p;
  p.start = x;
  p.end = x;
  return vf ? test::exact_vertex_face(p).hit : test::exact_edge_edge(p).hit;
}

Vec3 bump(Vec3 v, int axis, int dir) {
  v[axis] = std::nextafter(v[axis], dir > 0 ? HUGE_VAL : -HUGE_VAL);
  return v;
}

}  // namespace

TEST(CcdExactPredicates, Orient3dMatchesGmp) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> ex(-60, 60);
  int zeros = 0;
  for (int i = 0; i < 20000; ++i) {
    const double s = std::ldexp(1.0, ex(rng));
    Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    if (i % 2 == 0) {  // integer grid: the combinations below are exact
      for (Vec3* v : {&a, &b, &c}) *v = (*v * 1024).array().floor().matrix();
    }
    a *= s, b *= s, c *= s;
    Vec3 d;
    if (i % 2 == 0) {
      // On the plane of a, b, c when the dyadic combination is exact; else very close to it.
      const double r = std::ldexp(std::floor(u(rng) * 64), -5), q = std::ldexp(std::floor(u(rng) * 64), -5);
      d = a + r * (b - a) + q * (c - a);
      if (i % 4 == 0) d = bump(d, i % 3, (i / 4) % 2 ? 1 : -1);
    } else {
      d = Vec3(u(rng), u(rng), u(rng)) * s;
    }
    const int e = detail::exact_orient3d(a, b, c, d);
    ASSERT_EQ(e, gmp_orient3d(a, b, c, d)) << "case " << i;
    zeros += e == 0;
  }
  EXPECT_GT(zeros, 100);  // exact coplanarity is exercised
  // Points sharing one coordinate (a plane x = c, y = c or z = c), the others arbitrary: the
  // determinant's every term has a zero factor; with one point moved off the plane by an ulp,
  // not (then the plain evaluation rounds and the expansions decide).
  int shared_zeros = 0;
  for (int i = 0; i < 3000; ++i) {
    const int axis = i % 3;
    const double s = std::ldexp(1.0, ex(rng)), c = u(rng) * s;
    Vec3 p[4];
    for (Vec3& v : p) {
      v = Vec3(u(rng), u(rng), u(rng)) * s;
      v[axis] = c;
    }
    if (i % 2) p[i % 4] = bump(p[i % 4], axis, (i / 2) % 2 ? 1 : -1);
    const int e = detail::exact_orient3d(p[0], p[1], p[2], p[3]);
    ASSERT_EQ(e, gmp_orient3d(p[0], p[1], p[2], p[3])) << "shared-coordinate case " << i;
    shared_zeros += e == 0;
  }
  EXPECT_EQ(shared_zeros, 1500);
  // Points in one binade per coordinate ([1, 2), scaled): every difference is an exact double,
  // but on a grid of 2^-40 their products are not (the fixed-size path for exact differences,
  // between the plain evaluation and the general expansions). Half exactly coplanar (a dyadic
  // combination that stays on the grid), a quarter of those an ulp off, half general.
  int binade_zeros = 0;
  for (int i = 0; i < 20000; ++i) {
    const double s = std::ldexp(1.0, ex(rng));
    auto grid = [&] { return std::ldexp(std::floor((1.5 + u(rng) / 4) * 0x1p40), -40); };
    Vec3 p[4];
    for (int k = 0; k < 3; ++k) p[k] = Vec3(grid(), grid(), grid());
    if (i % 2 == 0) {
      const double r = std::ldexp(std::floor((u(rng) + 1) * 4), -5), q = std::ldexp(std::floor((u(rng) + 1) * 4), -5);
      p[3] = p[0] + r * (p[1] - p[0]) + q * (p[2] - p[0]);
      if (i % 8 == 0) p[3] = bump(p[3], (i / 8) % 3, (i / 8) % 2 ? 1 : -1);
    } else {
      p[3] = Vec3(grid(), grid(), grid());
    }
    for (Vec3& v : p) v *= s;
    for (int r = 1; r < 4; ++r)
      for (int k = 0; k < 3; ++k) ASSERT_EQ(mpq_class(p[r][k] - p[0][k]), mpq_class(p[r][k]) - mpq_class(p[0][k]));
    const int e = detail::exact_orient3d(p[0], p[1], p[2], p[3]);
    ASSERT_EQ(e, gmp_orient3d(p[0], p[1], p[2], p[3])) << "one-binade case " << i;
    binade_zeros += e == 0;
  }
  EXPECT_GT(binade_zeros, 5000);
  // Out of the exact range: unknown.
  EXPECT_EQ(detail::exact_orient3d(Vec3(0x1p-200, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)), 2);
}

TEST(CcdExactPredicates, TouchCertificatesOnGrids) {
  std::mt19937_64 rng(777);
  std::uniform_int_distribution<int> g(-64, 64);
  auto gp = [&](int e) { return Vec3(std::ldexp(g(rng), e), std::ldexp(g(rng), e), std::ldexp(g(rng), e)); };
  int vf_true = 0, ee_true = 0, vf_cases = 0, ee_cases = 0;
  for (int i = 0; i < 4000; ++i) {
    const int e = (i % 5) * 7 - 14;
    // VF: p = a + r (b - a) + q (c - a), with r, q >= 0, r + q <= 1 dyadic: touching (exact
    // when the arithmetic below is exact, which the GMP reference confirms).
    const Vec3 a = gp(e), b = gp(e), c = gp(e);
    const double r = std::ldexp(std::abs(g(rng)) % 33, -6), q = std::ldexp(std::abs(g(rng)) % 33, -6);
    std::array<Vec3, 4> vf{a + r * (b - a) + q * (c - a), a, b, c};
    for (int k = 0; k < 2; ++k) {
      const bool cert = detail::exact_vertex_face_touch(vf);
      const bool ref = gmp_touch(true, vf);
      if (cert) {
        EXPECT_TRUE(ref) << "VF certificate without contact, case " << i;
      }
      // Non-degenerate exact touch: the certificate must hold.
      if (ref && k == 0 && (b - a).cross(c - a).squaredNorm() > 0) {
        EXPECT_TRUE(cert) << "VF case " << i;
      }
      vf_true += cert;
      ++vf_cases;
      vf[0] = bump(vf[0], i % 3, 1);  // one ulp off: usually no contact
    }
    // EE: two segments through a common point x = a0 + s da = b0 + t db.
    const Vec3 a0 = gp(e), da = gp(e), db = gp(e);
    const double s = std::ldexp(std::abs(g(rng)) % 33, -5), t = std::ldexp(std::abs(g(rng)) % 33, -5);
    const Vec3 x = a0 + s * da;
    std::array<Vec3, 4> ee{a0, a0 + da, x - t * db, x + (1 - t) * db};
    if (i % 7 == 0) ee[2] = ee[0];  // shared end
    for (int k = 0; k < 2; ++k) {
      const bool cert = detail::exact_edge_edge_touch(ee);
      const bool ref = gmp_touch(false, ee);
      if (cert) {
        EXPECT_TRUE(ref) << "EE certificate without contact, case " << i;
      }
      if (ref && k == 0 && da.cross(db).squaredNorm() > 0) {
        EXPECT_TRUE(cert) << "EE case " << i;
      }
      ee_true += cert;
      ++ee_cases;
      ee[3] = bump(ee[3], (i + 1) % 3, -1);
    }
  }
  EXPECT_GT(vf_true, vf_cases / 4);
  EXPECT_GT(ee_true, ee_cases / 8);
}

// On every sample query, at t = 0 and t = 1 (the input doubles): a certificate implies contact.
TEST(CcdExactPredicates, SampleQueriesCertificatesAreSound) {
  const fs::path dir = test::data_dir() / "sample-queries";
  MCCD_REQUIRE_DATA(dir);
  int certs = 0, checked = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file() || e.path().extension() != ".csv") continue;
    const bool vf = e.path().string().find("vertex-face") != std::string::npos;
    for (const CcdQuery& q : read_query_csv(e.path().string())) {
      for (const auto* x : {&q.points.start, &q.points.end}) {
        const bool cert = vf ? detail::exact_vertex_face_touch(*x) : detail::exact_edge_edge_touch(*x);
        if (!cert) continue;
        ++certs;
        if (checked++ < 400) {
          EXPECT_TRUE(gmp_touch(vf, *x)) << e.path() << (vf ? " VF" : " EE");
        }
      }
    }
  }
  EXPECT_GT(certs, 0);
}
