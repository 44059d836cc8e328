#pragma once
/// @file Elementary continuous collision tests under linear motion over t in [0, 1]:
/// vertex-face (VF) and edge-edge (EE).
///
/// Contract (both tests): every point moves on a straight line from its start to its end
/// position. The answer is conservative: when the primitives touch or cross at some t in
/// [0, 1] (or come within `min_distance`), the test returns true, always, in floating point.
/// It may rarely return true for a pair that does not touch (a false positive). The reported
/// time of impact is never later than the true earliest one.
#include <array>
#include <cstdint>

#include "geometry/mesh.h"

namespace mccd {

/// Four points at the start (t = 0) and at the end (t = 1) of the step.
/// VF: {vertex, face corner 0, face corner 1, face corner 2}.
/// EE: {edge a end 0, edge a end 1, edge b end 0, edge b end 1}.
struct CcdPoints {
  std::array<Vec3, 4> start;
  std::array<Vec3, 4> end;
};

struct CcdOptions {
  /// Report pairs that come within this distance (>= 0).
  double min_distance = 0.0;
};

/// Per-stage counters, optional (pass nullptr). Not thread safe: one per thread.
struct CcdCounters {
  std::uint64_t queries = 0;
  std::uint64_t box_culled = 0;       ///< left after the swept-box test
  std::uint64_t coplanar_culled = 0;  ///< left after the Bernstein coplanarity filter
  std::uint64_t root_tests = 0;       ///< reached root isolation and the inside test
  std::uint64_t fallbacks = 0;        ///< undecided by the float bounds: exact / conservative path
  std::uint64_t hits = 0;
};

/// Vertex-face CCD. Returns true when the vertex may touch the triangle at some t in [0, 1];
/// then `toi` holds a conservative (never late) time of impact in [0, 1].
bool vertex_face_ccd(const CcdPoints& p, double& toi, const CcdOptions& options = {},
                     CcdCounters* counters = nullptr);

/// Edge-edge CCD. Returns true when the two segments may touch at some t in [0, 1];
/// then `toi` holds a conservative (never late) time of impact in [0, 1].
bool edge_edge_ccd(const CcdPoints& p, double& toi, const CcdOptions& options = {},
                   CcdCounters* counters = nullptr);

}  // namespace mccd
