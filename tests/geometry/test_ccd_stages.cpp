// Stage (b) of the elementary tests in its SSE2 form (both times of a vector in one register)
// against the one-vector-at-a-time reference: bit for bit the same differences, cross
// products, magnitudes and cubic, on random queries of every scale, with zeros of both signs,
// repeated points and non-finite coordinates. And the largest absolute coordinate of a query
// against the scalar chain of std::max.
#include <mccd/geometry/ccd_stages.h>

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <random>

using namespace mccd;
using namespace mccd::detail;

namespace {

CcdPoints random_query(std::mt19937_64& rng, int round) {
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> exponent(-70, 70), pick(0, 15);
  const double scale = std::ldexp(1.0, exponent(rng));
  CcdPoints p;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k) {
      p.start[i][k] = unit(rng) * scale;
      p.end[i][k] = p.start[i][k] + unit(rng) * scale * std::ldexp(1.0, -pick(rng));
    }
  // Special values on some rounds: signed zeros, a repeated point, infinity, NaN.
  switch (round % 8) {
    case 1: p.start[1] = p.start[0], p.end[1] = p.end[0]; break;
    case 2: p.start[2].x() = 0.0, p.end[3].y() = -0.0; break;
    case 3: p.end[2].z() = std::numeric_limits<double>::infinity(); break;
    case 4: p.start[3].y() = std::numeric_limits<double>::quiet_NaN(); break;
    case 5: p.start[0].setZero(), p.end[0].setZero(); break;
    default: break;
  }
  return p;
}

Setup<double> loaded(const CcdPoints& p) {
  Setup<double> S{};
  for (int i = 0; i < 4; ++i) {
    S.s[i] = {p.start[i].x(), p.start[i].y(), p.start[i].z()};
    S.e[i] = {p.end[i].x(), p.end[i].y(), p.end[i].z()};
  }
  return S;
}

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <CcdKind K>
void expect_same_stage_b(const CcdPoints& p, int round) {
  Setup<double> ref = loaded(p), fast = loaded(p);
  cubic_of<K>(ref);
  coplanarity_of<K>(fast);  // the SSE2 form where available
  const char* kind = K == CcdKind::VertexFace ? "VF" : "EE";
  for (auto [a, b, name] : {std::tuple{&ref.A0, &fast.A0, "A0"}, {&ref.A1, &fast.A1, "A1"}, {&ref.B0, &fast.B0, "B0"},
                            {&ref.B1, &fast.B1, "B1"}, {&ref.C0, &fast.C0, "C0"}, {&ref.C1, &fast.C1, "C1"},
                            {&ref.X00, &fast.X00, "X00"}, {&ref.X01, &fast.X01, "X01"}, {&ref.X10, &fast.X10, "X10"},
                            {&ref.X11, &fast.X11, "X11"}})
    EXPECT_TRUE(same_bits(*a, *b)) << kind << " " << name << ", round " << round;
  EXPECT_TRUE(same_bits(ref.alpha, fast.alpha)) << kind << " alpha, round " << round;
  EXPECT_TRUE(same_bits(ref.beta, fast.beta)) << kind << " beta, round " << round;
  EXPECT_TRUE(same_bits(ref.gamma, fast.gamma)) << kind << " gamma, round " << round;
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(same_bits(ref.f.c[k], fast.f.c[k])) << kind << " f.c[" << k << "], round " << round;
}

}  // namespace

TEST(CcdStages, CoplanarityCubicIsBitForBitTheReference) {
  std::mt19937_64 rng(20261124);
  for (int round = 0; round < 20000; ++round) {
    const CcdPoints p = random_query(rng, round);
    expect_same_stage_b<CcdKind::VertexFace>(p, round);
    expect_same_stage_b<CcdKind::EdgeEdge>(p, round);
    if (HasFailure()) break;
  }
}

TEST(CcdStages, LargestCoordinateSkipsNaNAsTheMaxChainDoes) {
  std::mt19937_64 rng(7);
  for (int round = 0; round < 20000; ++round) {
    CcdPoints p = random_query(rng, round);
    if (round % 5 == 0) p.end[1].z() = -std::numeric_limits<double>::quiet_NaN();
    double ref = 0;
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) ref = std::max(ref, std::fabs(p.start[i][k]));
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) ref = std::max(ref, std::fabs(p.end[i][k]));
    ASSERT_TRUE(same_bits(ref, max_abs_coordinate(p))) << "round " << round << ": " << ref << " vs " << max_abs_coordinate(p);
  }
}
