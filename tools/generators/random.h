#pragma once
/// @file A seeded random source whose numbers are the same on every platform and standard
/// library (std::uniform_real_distribution is not), so a scene is a function of its seed.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include <mccd/geometry/positions.h>

namespace mccd::gen {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  /// Uniform in [0, 1), 53 random bits.
  double uniform() { return double(engine_() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// A uniformly distributed unit vector.
  Vec3 unit_vector() {
    const double z = uniform(-1, 1), phi = uniform(0, 2 * std::numbers::pi), r = std::sqrt(1 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
  }
  /// A point uniformly distributed in the box [lo, hi].
  Vec3 in_box(const Vec3& lo, const Vec3& hi) { return {uniform(lo.x(), hi.x()), uniform(lo.y(), hi.y()), uniform(lo.z(), hi.z())}; }

 private:
  std::mt19937_64 engine_;  // its output sequence is fixed by the standard
};

}  // namespace mccd::gen
