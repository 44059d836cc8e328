#pragma once
/// @file The lane kernels of every SIMD level, for tests that compare them.
#include <vector>

#include <mccd/geometry/lane_masks.h>

namespace mccd::test {

/// The lane kernels of every SIMD level this build and processor have, scalar first.
inline std::vector<const detail::LaneKernels*> available_levels() {
  std::vector<const detail::LaneKernels*> out;
  for (detail::SimdLevel l :
       {detail::SimdLevel::Scalar, detail::SimdLevel::Sse2, detail::SimdLevel::Avx2, detail::SimdLevel::Avx512})
    if (const detail::LaneKernels* k = detail::lane_kernels_for(l)) out.push_back(k);
  return out;
}

/// Puts back the level in use when it goes out of scope (a test that selects levels).
struct KeepSimdLevel {
  detail::SimdLevel level = detail::lane_kernels().level;
  ~KeepSimdLevel() { detail::select_simd_level(level); }
};

}  // namespace mccd::test
