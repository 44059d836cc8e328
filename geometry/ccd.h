#pragma once
/// @file Elementary continuous collision tests under linear motion over t in [0, 1]:
/// vertex-face (VF) and edge-edge (EE).
///
/// Contract (both tests): every point moves on a straight line from its start to its end
/// position. The answer is conservative: when the primitives touch or cross at some t in
/// [0, 1] (or come within `min_distance`), the test returns true, always, in floating point.
/// It may rarely return true for a pair that does not touch (a false positive). The reported
/// time of impact is never later than the true earliest one.
///
/// How the answer is reached (swept boxes, the coplanarity filter, a certified fast path,
/// then a certified search over time pieces with exact shortcuts) is written down at the top
/// of geometry/ccd.cpp.
///
/// Degenerate cases, none of which can produce a false negative because every clearing
/// test is a necessary condition of contact proved with rigorous bounds:
///  - motion coplanar for all t (f == 0): the cubic clears nothing; the inside functions
///    and separating directions clear the pieces where the primitives are apart;
///  - parallel or collinear edges, zero-length edges, zero-area faces (g_i == 0 where the
///    normal vanishes): only separating directions clear; exact contacts are reported;
///  - vertex on an edge, edge endpoint on an edge, touching exactly at t = 0 or t = 1,
///    tangential (double-root) contact: undecided to the finest piece (or the budget), then
///    reported; touching exactly at t = 0 or t = 1: certified by the exact predicates; a
///    vertex or edge end passing through a segment while the two move in one plane (grids
///    folded along a grid line): certified at pieces of 2^-20, without the long-double pass;
///  - coordinates are rescaled by an exact power of two when the largest is outside
///    [2^-60, 2^60]; inputs that are not finite, or whose dynamic range exceeds about
///    2^1000, are reported as a contact at toi = 0 (conservative).
///
/// Time of impact: never later than the first contact. For a certified (transversal)
/// contact it lies within 2^-32 of the earliest root of the cubic in the certified piece,
/// unless the cubic is numerically zero over a wider span (then the start of that span).
/// For a reported undecided piece, and for a touch certified in one, it is the start of that
/// piece, the first time the tests could not clear (at most 2^-40, 2^-56 or 2^-100 before a contact
/// in that piece, at most 2^-20 before the certified touch, earlier when the primitives stay
/// within rounding distance of each other or a budget ran out). For a proved
/// touch at t = 1 it is 1 - 2^-40 (1 - 2^-24, 1 - 2^-12) or the start of the first piece
/// undecided at depth 16. With min_distance d > 0 it is 0 for pairs within d at t = 0, else
/// the start of the first piece that could not be cleared at distance d.
///
/// Cost: the box and coplanarity tests are cheap; queries decided by the fast path or the
/// min_distance shortcut cost more, and queries reaching the search the most (near-touching
/// and degenerate touching contacts away from t = 0 and t = 1 go to fine pieces), bounded by
/// the piece budgets (perf/bench_ccd.cpp measures each class).
#include <array>
#include <cstdint>

#include <mccd/geometry/mesh.h>

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
  std::uint64_t fast_hits = 0;        ///< contacts certified by the fast path (no search)
  std::uint64_t fast_misses = 0;      ///< pairs past the filters cleared by the fast path
  std::uint64_t pieces = 0;           ///< time pieces visited by the search (both passes)
  std::uint64_t touches = 0;          ///< touching contacts certified exactly in a plane (search)
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
