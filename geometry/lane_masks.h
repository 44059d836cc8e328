#pragma once
/// @file Internal: overlap tests of one coarse volume against many, the many stored as lanes
/// (structure of arrays), in the widest vector registers this processor has.
///
/// Coarse volumes are k-DOPs with 16-bit integer bounds on a grid (geometry/coarse_volumes.h).
/// A lane block holds those of up to 64 features side by side: row r is bound r of every
/// feature's volume (rows 0..slabs-1 the lower bounds, then the upper bounds), `stride`
/// values per row, a power of two from 8 to 64 and at least the number of lanes n, so one
/// vector load reads the same bound of 8, 16 or 32 features. Testing a volume against the block is then,
/// per bound, one broadcast and one comparison for a whole register of features.
///
/// Two volumes are apart along a slab when one's lower bound exceeds the other's upper bound
/// (touching counts as overlapping). Lanes at or past n are 0 in every result; a block may be
/// read up to kLaneSlack values past its last row.
///
/// The kernels are compiled for SSE2 (any x86-64), AVX2 and AVX-512 (BW) and chosen at run
/// time from what the processor supports; `MCCD_SIMD=scalar|sse2|avx2|avx512` in the
/// environment, or select_simd_level(), asks for a lower one. Other processors get a portable
/// scalar version. Every version returns the same bits.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace mccd::detail {

/// The instruction sets the kernels are compiled for, in increasing order.
enum class SimdLevel { Scalar, Sse2, Avx2, Avx512 };

/// Values a block may be read past its last row.
inline constexpr unsigned kLaneSlack = 64;
/// The most lanes one block holds (the bits of one mask).
inline constexpr unsigned kMaxLanes = 64;
/// LaneKernels::coplanar_quarters of a query it leaves to the filter itself.
inline constexpr std::uint8_t kUndecided = 0xFF;
/// LaneKernels::fast_tests: no contact, a certified contact, or left to the scalar test.
inline constexpr std::uint8_t kFastMiss = 0, kFastHit = 1, kFastOpen = 2;

/// One coarse k-DOP of at most 16 slabs on its own, for the kernels to test against blocks: its
/// lower bounds lo[0..slabs), its upper bounds hi[0..slabs) (the rest unused).
struct alignas(64) CoarseDop {
  std::int16_t lo[16], hi[16];
};

/// Where LaneKernels::vertex_quarters writes coarse volumes: a grid of nine slabs (origin and
/// scale per slab, as CoarseGrid<9>) and an array of them.
struct CoarseOut {
  const float* origin;
  const float* scale;
  CoarseDop* out;
};

/// One leaf's blocks for the kernels that test two leaves, or one, at once: its vertices', its
/// edges' and its faces' (rows, stride, lanes), and its own coarse volume.
struct LeafBlocks {
  const std::int16_t* vertices;
  unsigned vertex_stride, num_vertices;
  const std::int16_t* edges;
  unsigned edge_stride, num_edges;
  const std::int16_t* faces;
  unsigned face_stride, num_faces;
  const CoarseDop* leaf;
};

/// What LaneKernels::pair_masks finds for leaves A and B: the lanes of each side's vertices and
/// edges whose coarse volumes meet the other leaf's (alive_*); for each alive vertex j of A the
/// faces of B it meets (vertex_faces_ab[j]), likewise of B against A; for each alive edge i of A
/// the alive edges of B it meets (edges[i]). Entries of lanes not alive are left as they are.
struct PairMasks {
  std::uint64_t alive_va, alive_vb, alive_ea, alive_eb;
  std::uint64_t vertex_faces_ab[kMaxLanes], vertex_faces_ba[kMaxLanes], edges[kMaxLanes];
};

/// What LaneKernels::self_masks finds inside one leaf: for each of its vertices the faces it
/// meets, for each edge of `chosen` the edges it meets (entries of other lanes left as they are).
struct SelfMasks {
  std::uint64_t vertex_faces[kMaxLanes], edges[kMaxLanes];
};

struct LaneKernels {
  /// For each of `count` coarse k-DOPs others[i]: out[i] bit j set when lane j of the block
  /// `rows` (n <= 64 lanes, `stride` 8, 16, 32 or 64) overlaps it.
  void (*dops)(const std::int16_t* rows, unsigned stride, unsigned n, unsigned slabs, const CoarseDop* others,
               unsigned count, std::uint64_t* out);
  /// Leaves a and b's coarse tests against each other (PairMasks).
  void (*pair_masks)(unsigned slabs, const LeafBlocks& a, const LeafBlocks& b, PairMasks& out);
  /// Leaf l's coarse tests against itself (SelfMasks), its edges of `chosen` against all.
  void (*self_masks)(unsigned slabs, const LeafBlocks& l, std::uint64_t chosen, SelfMasks& out);
  /// Merges of lanes: out lane j (j < n) is the merge of the k (2 or 3) lanes sources[0][j],
  /// sources[1][j] (, sources[2][j]) of the block `rows` (at most 64 lanes, `stride` 8 to 64):
  /// along each of `slabs` slabs the least lower bound and the greatest upper bound. `out` a
  /// block of n <= 64 lanes and stride `out_stride`.
  void (*merge_lanes)(const std::int16_t* rows, unsigned stride, unsigned slabs, const std::uint8_t (*sources)[kMaxLanes],
                      unsigned k, unsigned n, std::int16_t* out, unsigned out_stride);
  /// The coplanarity filter (geometry/ccd_filter.h) of `n` queries of one kind without a
  /// minimum distance, points ids[i][0..3] (VF: the vertex, then the face's corners; EE: one
  /// edge's ends, then the other's) at positions x0 and x1 (x, y, z interleaved, by id), each
  /// in the quarters within[i]: quarters[i] = what FilteredCcd::filter returns for it, computed
  /// with the filter's own operations in its own order (bit for bit its values), when the
  /// points' largest coordinate is in [2^-60, 2^60] (no scaling); kUndecided otherwise.
  void (*coplanar_quarters)(bool vertex_face, const double* x0, const double* x1, const std::uint32_t (*ids)[4],
                            const std::uint8_t* within, std::size_t n, std::uint8_t* quarters);
  /// The fast path of the elementary test (geometry/ccd_fast.h) for `n` queries of one kind
  /// without a minimum distance, given as for coplanar_quarters, where it is simplest: a cubic
  /// with exactly one sign change on [0, 1] by Descartes' rule, its root bracketed, and a time
  /// of impact needing no bisection. decided[i] is kFastMiss, kFastHit (toi[i] set) or
  /// kFastOpen: whatever the scalar fast path would decide otherwise (a split, a bisection,
  /// the separation test), and points whose largest coordinate is outside [2^-60, 2^60], is
  /// left open. A decided query has the scalar test's answer and time of impact bit for bit:
  /// the same operations in the same order, a query per lane.
  void (*fast_tests)(bool vertex_face, const double* x0, const double* x1, const std::uint32_t (*ids)[4],
                     std::size_t n, std::uint8_t* decided, double* toi);
  /// core/self_culling.cpp's star_sign (the orientation of a moving triangle seen from a moving
  /// point: -1, 0 or +1, certain over the step) for `n` triangles, corners[i] (vertex ids) at
  /// positions x0 and x1, seen from m0 at t = 0 and m1 at t = 1: signs[i], its operations in its
  /// order, a triangle per lane (bit for bit its values); `bound` and `tiny` its constants.
  void (*star_signs)(const double* x0, const double* x1, const std::uint32_t (*corners)[3], std::size_t n,
                     const double* m0, const double* m1, double bound, double tiny, std::int8_t* signs);
  /// core/self_culling.cpp's normal_signs with every axis wanted, for `n` triangles given as
  /// for star_signs: bits[i] (not written when `bits` is nullptr), its operations in its order,
  /// a triangle per lane; `bound` and `tiny` its constants. Returns the bits all n triangles
  /// have (their and; 0x3F when n is 0).
  unsigned (*normal_signs)(const double* x0, const double* x1, const std::uint32_t (*corners)[3], std::size_t n,
                           double bound, double tiny, std::uint8_t* bits);
  /// geometry/swept_volumes.h's 18-DOP volumes of a vertex over the four quarters of a step,
  /// its operations in its order, a vertex per lane (bit for bit its values): for the n <= 64
  /// vertices vertex_of_slot[i] at positions x0 and x1 (x, y, z interleaved, by id), inflated
  /// by `min_distance`, the 72 floats of a QuarterDop<9> at out + 72 i, except where bit i of
  /// `skip` is set (left as they are). With `coarse` (else nullptr), also the coarse volume of
  /// each one written, on the grid coarse->origin, coarse->scale (CoarseGrid<9>::quantize of the
  /// quarters' merge, bit for bit), into coarse->out[i]. nullptr where this level has no such
  /// kernel (the caller computes them itself).
  void (*vertex_quarters)(const double* x0, const double* x1, const std::uint32_t* vertex_of_slot, std::size_t n,
                          double min_distance, std::uint64_t skip, float* out, const CoarseOut* coarse);
  /// geometry/quarter_volumes.h's QuarterDop<9>::merge_each for the n volumes (72 floats each)
  /// at base + 72 slots[i] (slots nullptr: base + 72 i), merged into `acc` (72 floats): each
  /// lower bound the minimum and each upper bound the maximum, in its order and with its
  /// operands' order (bit for bit its values, NaN included). nullptr where this level has no
  /// such kernel (the caller merges them itself).
  void (*merge_quarters)(const float* base, const std::uint32_t* slots, std::size_t n, float* acc);
  SimdLevel level;
};

/// The kernels in use (the best level this processor supports, or the one asked for).
const LaneKernels& lane_kernels();
/// The best level this processor supports.
SimdLevel best_simd_level();
/// The kernels of `level`, if this build and processor have it (nullptr otherwise).
const LaneKernels* lane_kernels_for(SimdLevel level);
/// Uses `level` from now on (process-wide: tests and benchmarks compare the levels); throws
/// mccd::Error when this processor or build lacks it.
void select_simd_level(SimdLevel level);
const char* to_string(SimdLevel level);
/// "scalar", "sse2", "avx2", "avx512"; nullopt for anything else.
std::optional<SimdLevel> parse_simd_level(const std::string& name);

}  // namespace mccd::detail
