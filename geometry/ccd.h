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
/// Method (geometry/ccd.cpp has the error analysis):
///  (a) swept boxes: the axis-aligned boxes of each primitive over [0, 1] (exact comparisons);
///  (b) coplanarity filter: the cubic f(t) = det of the three difference vectors, in Bernstein
///      form over [0, 1] with a rigorous forward error bound; four coefficients of one sign
///      beyond the bound (beyond d * max|normal| when min_distance = d > 0) prove that the
///      points are never coplanar, hence never touch. Most pairs leave at (a) or (b);
///  (c0) min_distance = d > 0: pairs certainly within d at t = 0 (corner to corner, corner to
///      segment, or the interior case, with rigorous bounds; geometry/ccd_distance.h) are
///      contacts at toi = 0, without a search;
///  (c1) fast path (d = 0; geometry/ccd_fast.h): the roots of the cubic are isolated from its
///      Bernstein coefficients (Descartes' rule of signs, splitting at its critical points),
///      each bracketed within a few ulps of time by two evaluations of the cubic with
///      certain signs, and the inside functions at the bracket's ends bound them over it. A
///      root where some g_i is certainly negative has no contact; the first root where every
///      g_i is certainly positive is a certified contact (toi on the grid of 2^-32 below it).
///      Every root rejected: no contact. Where the roots cannot be isolated (the cubic within
///      its error bound at t = 0 or t = 1, as for primitives moving in one plane), one
///      separation test over [0, 1]. Anything undecided goes to the search, so the answer is
///      the search's answer or a better one (the fast path never reports a pair that does
///      not touch). On the real cloth-ball step it decides about 100% of the true contacts
///      and 95% of the pairs past (b);
///  (c) a depth-first search over dyadic time pieces, earliest first. On each piece the cubic
///      and the inside functions g_i (VF: the barycentric coordinates times |n|^2; EE: the
///      two segment parameters and their complements times |da x db|^2), all quartics in
///      Bernstein form with error bounds, are enclosed. A piece is cleared when the cubic is
///      certainly nonzero, or some g_i is certainly negative (d = 0), or a separating
///      direction (closest points, face normal, in-plane edge normals, da x db and its
///      in-plane normals) holds over the whole piece, checked rigorously. It is a certified
///      contact when the cubic certainly changes sign and every g_i is certainly positive.
///      Undecided pieces are halved; pieces still undecided at 2^-40 are handed to the same
///      search in long double (64-bit mantissa, error bounds ~2^11 times smaller) down to
///      2^-56; what stays undecided is reported as a contact at the start of that piece.
///      Shortcuts (geometry/ccd_exact.h: exact predicates on the input doubles with
///      floating-point expansions, behind floating-point filters):
///       - touching exactly at t = 0 (exact coplanarity and inside tests at the start
///         positions) is certified at once: toi = 0;
///       - touching exactly at t = 1 is proved the same way on the end positions (lazily,
///         once, when the values at t = 1 allow it); then a piece reaching t = 1 whose earlier
///         part [lo, 1 - 2^-k] (k = 40, 24, 12) is certainly free of coplanarity ends the
///         search with toi = 1 - 2^-k, and any piece undecided at depth >= 16 ends it with
///         toi = its start (every earlier piece is cleared, so this is never late);
///       - on a piece where the cubic certainly changes sign, its sign change is located by
///         bracketed floating-point Newton steps and the piece is replaced by a window of
///         width 2^(k+1-D) (D the maximum depth of the pass, k = 3, 8 or 13) around it,
///         once the cubic is proved (rigorous bounds, polynomials restricted from [0, 1])
///         certainly nonzero on the rest of the piece: about D - k levels of bisection are
///         skipped;
///       - a piece undecided at 2^-20 or finer (or when the budget runs out) is offered to
///         an exact certificate of touching without crossing (geometry/ccd_touch.h), before
///         any long-double pass: the vertex (VF) or an edge end (EE) and the segment it
///         meets, with their six start and end points exactly coplanar (exact orient3d), the
///         point crossing the segment's line strictly inside the segment within the piece or
///         [lo, lo + 2^-30] or [lo, lo + 2^-20] (rigorous bounds on three quadratics). A
///         certified touch is a contact at toi = the piece's start;
///       - on pieces at depths 0, 4, 8, 12 and 16, the same certificate is offered a window
///         [a, a + 2^-20] (on the grid of 2^-20, a >= the piece's start) around where a point
///         crosses a segment's line (the point-segment pairs in turn); when it certifies a
///         touch there and [start, a] is cleared in one piece by the tests of any piece, the
///         search ends with toi = a (the first contact lies in the window): the primitives
///         that move in one plane reach their touch in a few pieces instead of bisecting down
///         to 2^-20;
///       - piece budgets: 200 pieces in double, 8 in long double per query; a query that
///         exhausts them is reported as a contact at the start of the current piece.
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
/// piece, the first time the tests could not clear (at most 2^-40 or 2^-56 before a contact
/// in that piece, at most 2^-20 before the certified touch, earlier when the primitives stay
/// within rounding distance of each other or a budget ran out). For a proved
/// touch at t = 1 it is 1 - 2^-40 (1 - 2^-24, 1 - 2^-12) or the start of the first piece
/// undecided at depth 16. With min_distance d > 0 it is 0 for pairs within d at t = 0, else
/// the start of the first piece that could not be cleared at distance d.
///
/// Cost: ~20 ns (box) and ~60 ns (coplanarity) per query; queries decided by the fast path
/// or the min_distance shortcut a few hundred ns; queries reaching the search from ~1 us to a
/// few tens of microseconds (near-touching and degenerate touching contacts that are not at
/// t = 0 or t = 1 still go to fine pieces; touches certified in one plane about 2-5 us, where
/// the long-double pass took about 12 us); bounded by the piece budgets.
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
