#pragma once
/// @file Internal: the stages of the elementary CCD tests, exposed for the benchmark and the
/// tests. Not part of the public API; may change without notice.
#include <mccd/geometry/ccd.h>

namespace mccd::detail {

enum class CcdKind { VertexFace, EdgeEdge };

/// Stage (a): the swept boxes of the two primitives (over t in [0, 1]) come within
/// `min_distance` of each other. False proves that the primitives never do.
bool ccd_box_overlap(CcdKind kind, const CcdPoints& p, double min_distance);

/// Stage (b): the Bernstein coplanarity filter. False proves that the four points are never
/// coplanar (within `min_distance`) on [0, 1], hence no contact. Does not apply stage (a).
bool ccd_coplanarity_may_hit(CcdKind kind, const CcdPoints& p, double min_distance);

/// Whether stage (c) tries the fast path (geometry/ccd_fast.h) before the search.
enum class CcdPath { Fast, SearchOnly };

/// The whole test (stages a, b, c), as called by vertex_face_ccd / edge_edge_ccd. SearchOnly
/// skips the fast path: the tests and the benchmark compare the two.
bool ccd_run(CcdKind kind, const CcdPoints& p, double& toi, const CcdOptions& options, CcdCounters* counters,
             CcdPath path = CcdPath::Fast);

/// Tuning constants of stage (c), documented in ccd.h.
inline constexpr int kCcdMaxDepth = 40;          ///< double pass: pieces down to 2^-40
inline constexpr int kCcdPieceBudget = 600;      ///< double pass: at most this many pieces
inline constexpr int kCcdMaxDepthLong = 56;      ///< long double pass: pieces down to 2^-56
inline constexpr int kCcdPieceBudgetLong = 64;   ///< long double pass: at most this many pieces (per query)
inline constexpr int kCcdMaxDepthQuad = 100;     ///< quad pass: pieces down to 2^-100 (binary128)
inline constexpr int kCcdPieceBudgetQuad = 16;   ///< quad pass: at most this many pieces (per query)
inline constexpr int kCcdToiDepth = 32;          ///< certified contacts: toi refined to 2^-32
inline constexpr int kCcdCertDepth = 16;         ///< undecided from here: a proved touch at t = 1 ends the search
inline constexpr int kCcdTouchDepth = 20;        ///< double pass: the touch certificate tried on pieces of 2^-20 and finer

}  // namespace mccd::detail
