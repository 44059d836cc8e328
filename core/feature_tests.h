#pragma once
/// @file Internal: the test of one feature pair, the same for every method and every way of
/// reaching the pair (a leaf pair of either representative rule, the orphan set, brute
/// force), so that all of them report identical contacts (geometry/swept_volumes.h, the
/// consistency invariant):
///  1. the features' quarter volumes must overlap in some quarter (a whole-step test first
///     where it is cheaper; it is implied);
///  2. the narrow phase, a template parameter (ipc-toolkit passes its narrow phase the same way,
///     at run time), in two parts: its filter, which names the quarters where the pair may
///     still touch (the default: the coplanarity filter, geometry/ccd_filter.h), and, when a
///     simulator query does not say otherwise (core/query.h), its test.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <type_traits>
#include <vector>

#include <mccd/core/executor.h>
#include <mccd/core/query.h>
#include <mccd/core/worker_output.h>
#include <mccd/geometry/ccd.h>
#include <mccd/geometry/ccd_filter.h>
#include <mccd/geometry/lane_masks.h>
#include <mccd/geometry/swept_volumes.h>

namespace mccd::detail {

/// The default narrow phase: mccd's conservative elementary tests (geometry/ccd.h), their
/// coplanarity filter first (geometry/ccd_filter.h); the test continues the filter's work.
/// A narrow phase provides a per-pair `Query` and these two calls.
struct ConservativeCcd {
  CcdOptions options;
  using Query = FilteredCcd;
  /// The quarters of `within` in which the pair may touch (0: it cannot).
  unsigned filter(Query& q, CcdKind kind, const CcdPoints& p, unsigned within) const {
    return q.filter(kind, p, options.min_distance, within);
  }
  /// filter() where the vector filter already returned `known` for quarters holding `within`.
  unsigned filter_known(Query& q, CcdKind kind, const CcdPoints& p, unsigned within, unsigned known) const {
    return q.filter_known(kind, p, within, known);
  }
  /// The elementary test, after filter() returned non-zero for the same query.
  bool test(Query& q, CcdKind kind, double& toi, StepStats& s) const {
    return q.test(toi, kind == CcdKind::VertexFace ? &s.vf_ccd : &s.ee_ccd);
  }
};

/// Reads the step's positions (interleaved doubles, global vertex ids), volumes and query state
/// through references owned by the stepper, so one object serves every step.
template <BoundingVolume BV, class NarrowPhase = ConservativeCcd>
class FeatureTests {
 public:
  using Quarters = QuarterVolume<BV>;

  FeatureTests(const MeshTopology& topo, const SweptVolumes<BV>& swept, const Positions& x0, const Positions& x1,
               QueryState& query, NarrowPhase narrow)
      : topo_(topo), swept_(swept), x0_(x0), x1_(x1), query_(query), narrow_(narrow) {}

  const MeshTopology& topology() const { return topo_; }
  const SweptVolumes<BV>& swept() const { return swept_; }
  const QueryState& query() const { return query_; }

  /// Vertex v against face f (v not a corner of f). `within`: quarters known to hold every
  /// quarter in which the two can meet (from volumes containing theirs), all four otherwise.
  void test_vf(std::uint32_t v, std::uint32_t f, WorkerOutput& out, unsigned within = 0xF) const {
    if (query_.stopped()) return;
    ++out.stats.feature_box_tests;
    if (!swept_.vertex(v).overlaps(swept_.face(f))) return;
    const Triangle& t = topo_.faces()[f];
    test_vf_quarters(v, swept_.vertex_quarters(v), t, f, swept_.face_quarters(t), out, within);
  }

  /// The same after the whole-step test, with the vertex's and the face's quarters at hand.
  void test_vf_quarters(std::uint32_t v, const Quarters& vertex_quarters, const Triangle& t, std::uint32_t f,
                        const Quarters& face_quarters, WorkerOutput& out, unsigned within) const {
    const unsigned quarters = vertex_quarters.overlap_mask(face_quarters, within);
    if (quarters) narrow({v, t[0], t[1], t[2]}, v, f, ContactKind::VertexFace, quarters, out);
  }

  /// Edges a and b (sharing no vertex). `within` as for test_vf.
  void test_ee(std::uint32_t a, std::uint32_t b, WorkerOutput& out, unsigned within = 0xF) const {
    test_ee(a, b, swept_.edge_quarters(a), swept_.edge_quarters(b), out, within);
  }

  /// The same with the edges' quarters at hand.
  [[gnu::always_inline]] void test_ee(std::uint32_t a, std::uint32_t b, const Quarters& qa, const Quarters& qb,
                                      WorkerOutput& out, unsigned within) const {
    if (query_.stopped()) return;
    ++out.stats.feature_box_tests;
    if (const unsigned quarters = qa.overlap_mask(qb, within)) test_ee_quarters(a, b, quarters, out);  // symmetric test
  }

  /// Edges a and b (sharing no vertex) whose quarter volumes overlap in the quarters `quarters`
  /// (non-zero; the caller tested them and counted the test): the narrow phase.
  void test_ee_quarters(std::uint32_t a, std::uint32_t b, unsigned quarters, WorkerOutput& out) const {
    test_ee_quarters(a, topo_.edges()[a], b, topo_.edges()[b], quarters, out);
  }
  /// The same with the edges' ends at hand (a leaf pair keeps them in leaf order).
  void test_ee_quarters(std::uint32_t a, const Edge& ea, std::uint32_t b, const Edge& eb, unsigned quarters,
                      WorkerOutput& out) const {
    if (query_.stopped()) return;
    // reported as (lower id, higher id)
    if (a < b)
      narrow({ea[0], ea[1], eb[0], eb[1]}, a, b, ContactKind::EdgeEdge, quarters, out);
    else
      narrow({eb[0], eb[1], ea[0], ea[1]}, b, a, ContactKind::EdgeEdge, quarters, out);
  }

  /// Feature pairs past their volume tests wait in out.queued, and run_queued() sends them to
  /// the narrow phase together, in order: most are pairs that the coplanarity filter removes,
  /// and the filter runs for several pairs at a time in vector registers first
  /// (LaneKernels::coplanar_quarters: its own values); in a full step so does the elementary
  /// tests' fast path for the pairs it keeps (LaneKernels::fast_tests), and only the pairs
  /// that path leaves open go through the narrow phase one by one (which runs the filter
  /// again, to the same result).
  static constexpr std::size_t kQueue = 256;

  /// Whether run_queued() runs the coplanarity filter for several queued pairs at a time in
  /// vector registers before the narrow phase (the default narrow phase without a minimum
  /// distance).
  bool prefilters() const {
    if constexpr (std::is_same_v<NarrowPhase, ConservativeCcd>) return !(narrow_.options.min_distance > 0);
    return false;
  }

  /// Bit of QueuedPair::quarters: the pair's own quarter volumes are not tested yet (the low
  /// four bits then name quarters known to hold every quarter in which they overlap, such as
  /// those of its leaves); run_queued() tests them after the coplanarity filter, only for the
  /// pairs it keeps. Same contacts, times and elementary tests either way: the filter decides
  /// each quarter on its own, so the filter over more quarters, intersected with the volumes'
  /// quarters, is the filter over the volumes' quarters.
  static constexpr std::uint8_t kVolumesPending = 0x10;

  /// The queue entries (out.queued) of a vertex-face pair and of an edge-edge pair (sharing no
  /// vertex) whose quarter volumes overlap in `quarters` (empty: not queued), or with
  /// kVolumesPending, whose volumes are to be tested after the filter in the quarters named.
  /// Built without a branch: loops write every pair at the queue's end and keep those whose
  /// quarters are not empty by moving the end (PairQueue::room()).
  static QueuedPair vf_entry(std::uint32_t v, const Triangle& t, std::uint32_t f, unsigned quarters,
                             std::uint32_t leaf_a, std::uint32_t leaf_b) {
    return {{v, t[0], t[1], t[2]}, v, f, leaf_a, leaf_b, 0, static_cast<std::uint8_t>(quarters)};
  }
  /// The lower edge id first (a != b). Without a branch: which edge comes first is as good as
  /// random in a leaf pair's loops, where a branch on it is mispredicted often.
  static QueuedPair ee_entry(std::uint32_t a, const Edge& ea, std::uint32_t b, const Edge& eb, unsigned quarters,
                             std::uint32_t leaf_a, std::uint32_t leaf_b) {
    std::uint64_t xa, xb;  // each edge's two ends as one word
    std::memcpy(&xa, ea.data(), sizeof xa);
    std::memcpy(&xb, eb.data(), sizeof xb);
    std::uint64_t swap = std::uint64_t(0) - std::uint64_t(b < a);
#if defined(__GNUC__)
    asm("" : "+r"(swap));  // opaque: the compiler would turn the selection back into a branch
#endif
    const std::uint64_t first = xa ^ ((xa ^ xb) & swap);
    const std::uint64_t second = xa ^ xb ^ first;
    QueuedPair p;
    std::memcpy(p.ids, &first, sizeof first);
    std::memcpy(p.ids + 2, &second, sizeof second);
    const std::uint64_t ab = a | std::uint64_t(b) << 32, ba = b | std::uint64_t(a) << 32;
    const std::uint64_t ids = ab ^ ((ab ^ ba) & swap);  // (a, b) in that order, or swapped
    p.a = static_cast<std::uint32_t>(ids);
    p.b = static_cast<std::uint32_t>(ids >> 32);
    p.leaf_a = leaf_a;
    p.leaf_b = leaf_b;
    p.kind = 1;
    p.quarters = static_cast<std::uint8_t>(quarters);
    return p;
  }

  /// Queued pairs per piece of a queue whose pieces run in parallel (set_executor()), and the
  /// pairs a unit (a front block, a task) must have queued before its queues are cut so.
  static constexpr std::size_t kPiece = 128, kHeavyUnit = 4 * kQueue;

  /// With an executor (nullptr: none), the queues of a heavy unit run in parallel pieces
  /// (run_queued()): a contact region whose leaf pairs queue thousands of feature pairs is
  /// otherwise one task's narrow phase, the longest of a step on many threads. Other units'
  /// queues run whole, without the pieces' cost.
  void set_executor(const Executor* executor) { executor_ = executor; }

  /// The narrow phase of every queued pair (until the query stops); found(leaf_a, leaf_b) for
  /// each pair that adds a contact. With an executor, once the unit has queued kHeavyUnit
  /// pairs, in pieces of kPiece pairs in parallel, each into its own output, then added to
  /// `out` in order: the same contacts in the same order and the same counts as in one piece.
  template <class Found>
  void run_queued(WorkerOutput& out, const Found& found) const {
    const std::size_t n = out.queued.size();
    const QueuedPair* q = out.queued.data();
    if (!executor_ || n < 2 * kPiece || out.queued.total() < kHeavyUnit) {
      run_pairs(q, n, out, found);
    } else {
      const std::size_t pieces = (n + kPiece - 1) / kPiece;
      std::vector<WorkerOutput> parts(pieces - 1);  // piece 0 writes to `out` itself
      executor_->dynamic_for(pieces, 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k != e; ++k)
          run_pairs(q + k * kPiece, std::min(kPiece, n - k * kPiece), k == 0 ? out : parts[k - 1], found);
      });
      for (const WorkerOutput& part : parts) {
        out.contacts.insert(out.contacts.end(), part.contacts.begin(), part.contacts.end());
        out.stats += part.stats;
      }
    }
    out.queued.clear();
  }

  /// The narrow phase of the queued pairs w0[0, count), in order, into `out` (its contacts and
  /// counts only). In a full step the fast path of the elementary tests runs for several pairs
  /// at a time too (LaneKernels::fast_tests), for the pairs whose filter the vector filter
  /// decided; what it leaves open goes through the narrow phase one by one. The contacts, their
  /// order and every count are those of the narrow phase alone.
  template <class Found>
  void run_pairs(const QueuedPair* w0, std::size_t count, WorkerOutput& out, const Found& found) const {
    const bool prefilter = prefilters();
    const bool batch = prefilter && query_.kind() == StepKind::Full;
    constexpr std::size_t kWindow = 2 * kQueue;
    std::uint8_t filtered[kWindow];  // the filter's result, or kUndecided
    // each kind's pairs together (the vertex-face pairs from the front of the arrays, the
    // edge-edge pairs from the back): their ids, their quarters, where they are in the window
    std::uint32_t ids[kWindow][4];
    std::uint8_t within[kWindow], r[kWindow];
    std::uint16_t where[kWindow];
    // batch: what each pair needs (kSkip, kNarrow, kFast), its quarters, the fast path's
    // decision and time of impact
    enum : std::uint8_t { kSkip, kNarrow, kFast };
    std::uint8_t action[kWindow], quarters_at[kWindow], decided[kWindow];
    double toi_at[kWindow], toi_lanes[kWindow];
    for (std::size_t first = 0; first < count && !query_.stopped(); first += kWindow) {
      const std::size_t n = std::min(kWindow, count - first);
      const QueuedPair* w = w0 + first;
      std::fill(filtered, filtered + n, kUndecided);
      if (prefilter) {
        // ids and quarters gathered in one pass (the filter decides each pair on its own, in
        // any order)
        std::size_t nvf = 0, back = kWindow;
        for (std::size_t i = 0; i < n; ++i) {
          const std::size_t j = w[i].kind == 0 ? nvf++ : --back;
          // the positions lie by vertex id: asked for while the window is gathered
          for (std::uint32_t v : w[i].ids) {
            __builtin_prefetch(x0_.data() + 3 * std::size_t(v));
            __builtin_prefetch(x1_.data() + 3 * std::size_t(v));
          }
          std::memcpy(ids[j], w[i].ids, sizeof(ids[j]));
          within[j] = w[i].quarters & 0xFu;
          where[j] = static_cast<std::uint16_t>(i);
        }
        const std::size_t nee = kWindow - back;
        if (nvf) lane_kernels().coplanar_quarters(true, x0_.data(), x1_.data(), ids, within, nvf, r);
        if (nee) lane_kernels().coplanar_quarters(false, x0_.data(), x1_.data(), ids + back, within + back, nee, r + back);
        for (std::size_t j = 0; j < nvf; ++j) filtered[where[j]] = r[j];
        for (std::size_t j = back; j < kWindow; ++j) filtered[where[j]] = r[j];
      }
      if (batch) {
        // what each pair needs, and the fast path for those the vector filter decided
        std::size_t nvf = 0, back = kWindow;
        for (std::size_t i = 0; i < n; ++i) {
          prefetch_ahead(w, filtered, i, n);
          action[i] = kSkip;
          const unsigned quarters = kept_quarters(w[i], filtered[i], out);
          if (!quarters) continue;
          quarters_at[i] = static_cast<std::uint8_t>(quarters);
          if (!known(w[i], filtered[i], quarters)) {
            action[i] = kNarrow;
            continue;
          }
          if (!(filtered[i] & quarters)) {  // what narrow() finds and counts at once
            ++(w[i].kind == 0 ? out.stats.vf_filtered : out.stats.ee_filtered);
            continue;
          }
          action[i] = kFast;
          const std::size_t j = w[i].kind == 0 ? nvf++ : --back;
          std::memcpy(ids[j], w[i].ids, sizeof(ids[j]));
          where[j] = static_cast<std::uint16_t>(i);
        }
        const std::size_t nee = kWindow - back;
        if (nvf) lane_kernels().fast_tests(true, x0_.data(), x1_.data(), ids, nvf, r, toi_lanes);
        if (nee) lane_kernels().fast_tests(false, x0_.data(), x1_.data(), ids + back, nee, r + back, toi_lanes + back);
        for (std::size_t j = 0; j < nvf; ++j) decided[where[j]] = r[j], toi_at[where[j]] = toi_lanes[j];
        for (std::size_t j = back; j < kWindow; ++j) decided[where[j]] = r[j], toi_at[where[j]] = toi_lanes[j];
        for (std::size_t i = 0; i < n; ++i) {
          if (action[i] == kSkip) continue;
          const QueuedPair& p = w[i];
          if (action[i] == kFast && decided[i] != kFastOpen) {
            const std::size_t before = out.contacts.size();
            fast_decided(p, filtered[i] & quarters_at[i], decided[i] == kFastHit, toi_at[i], out);
            if (out.contacts.size() != before) found(p.leaf_a, p.leaf_b);
          } else {
            narrow_queued(p, quarters_at[i], action[i] == kFast ? filtered[i] : kUndecided, out, found);
          }
        }
        continue;
      }
      for (std::size_t i = 0; i < n && !query_.stopped(); ++i) {
        prefetch_ahead(w, filtered, i, n);
        const QueuedPair& p = w[i];
        const unsigned quarters = kept_quarters(p, filtered[i], out);
        if (!quarters) continue;
        // The filter's own result for the quarters the vector filter was asked (those of the
        // queued pair, holding the pair's own): not computed twice.
        narrow_queued(p, quarters, known(p, filtered[i], quarters) ? filtered[i] : kUndecided, out, found);
      }
    }
  }

  /// An earliest-impact query skips what cannot meet before the best time found so far.
  bool too_late(unsigned quarters) const {
    return query_.kind() == StepKind::Earliest && 0.25 * std::countr_zero(quarters) >= query_.best();
  }

 private:
  /// Pairs ahead whose volumes, tested after the filter, run_queued() asks for.
  static constexpr std::size_t kAhead = 4;
  /// Asks for the volumes of the pair kAhead after pair i of a window of n (when they are
  /// tested after the filter and the filter keeps the pair).
  void prefetch_ahead(const QueuedPair* w, const std::uint8_t* filtered, std::size_t i, std::size_t n) const {
    if (i + kAhead < n && (w[i + kAhead].quarters & kVolumesPending) && filtered[i + kAhead] != 0)
      prefetch_volumes(w[i + kAhead]);
  }
  /// narrow() on queued pair p in `quarters` (`known` as for narrow()), and found(leaf_a,
  /// leaf_b) when it adds a contact.
  template <class Found>
  void narrow_queued(const QueuedPair& p, unsigned quarters, unsigned known, WorkerOutput& out, const Found& found) const {
    const std::size_t before = out.contacts.size();
    narrow({p.ids[0], p.ids[1], p.ids[2], p.ids[3]}, p.a, p.b,
           p.kind == 0 ? ContactKind::VertexFace : ContactKind::EdgeEdge, quarters, out, known);
    if (out.contacts.size() != before) found(p.leaf_a, p.leaf_b);
  }
  /// The quarters in which queued pair p goes to the narrow phase (0: none, the pair's counts
  /// made), `filtered` the vector filter's result for it (or kUndecided): its own quarter
  /// volumes' when they are pending, and none when the filter clears those.
  unsigned kept_quarters(const QueuedPair& p, std::uint8_t filtered, WorkerOutput& out) const {
    if (filtered == 0) {
      ++(p.kind == 0 ? out.stats.vf_filtered : out.stats.ee_filtered);  // what narrow() counts for it
      return 0;
    }
    unsigned quarters = p.quarters & 0xFu;
    if (p.quarters & kVolumesPending) {
      quarters = volume_quarters(p);
      if (!quarters) return 0;  // the volumes never meet in a common quarter
      if (filtered != kUndecided && !(filtered & quarters)) {
        ++(p.kind == 0 ? out.stats.vf_filtered : out.stats.ee_filtered);
        return 0;
      }
    }
    return quarters;
  }
  /// Whether the vector filter's result for p holds `quarters` (those it was asked for hold
  /// them): the narrow phase then takes it instead of running the filter again.
  static bool known(const QueuedPair& p, std::uint8_t filtered, unsigned quarters) {
    return filtered != kUndecided && !(quarters & ~(p.quarters & 0xFu));
  }
  /// What narrow() does for pair p, known to the vector filter with `kept` quarters (not 0),
  /// when the fast path decided it (LaneKernels::fast_tests): `hit` with `toi`, or no contact;
  /// the same counts as the test's (FilteredCcd::test and its fast path).
  void fast_decided(const QueuedPair& p, unsigned kept, bool hit_found, double toi, WorkerOutput& out) const {
    const bool vf = p.kind == 0;
    const ContactKind kind = vf ? ContactKind::VertexFace : ContactKind::EdgeEdge;
    const RawContact pair{RawContact::make_key(kind, p.a, p.b), 0.25 * std::countr_zero(kept),
                          {p.ids[0], p.ids[1], p.ids[2], p.ids[3]}};
    ++(vf ? out.stats.vf_tests : out.stats.ee_tests);
    CcdCounters& c = vf ? out.stats.vf_ccd : out.stats.ee_ccd;
    ++c.queries, ++c.root_tests;
    if (!hit_found) {
      ++c.fast_misses;
      return;
    }
    ++c.fast_hits, ++c.hits;
    hit(pair, std::max(toi, pair.toi), out);
  }
  /// The quarters in which a queued pair's own quarter volumes overlap (VF: the vertex's
  /// against the face's; EE: edge a's against edge b's).
  unsigned volume_quarters(const QueuedPair& p) const {
    if (p.kind == 0) return swept_.vertex_quarters(p.a).overlap_mask(swept_.face_quarters({p.ids[1], p.ids[2], p.ids[3]}));
    // an edge's quarters from its ends' (the ids), as edge_quarters() merges them
    return Quarters::merged(swept_.vertex_quarters(p.ids[0]), swept_.vertex_quarters(p.ids[1]))
        .overlap_mask(Quarters::merged(swept_.vertex_quarters(p.ids[2]), swept_.vertex_quarters(p.ids[3])));
  }
  /// Asks for what volume_quarters(p) reads.
  void prefetch_volumes(const QueuedPair& p) const {
    for (std::uint32_t v : p.ids) {
      const char* q = reinterpret_cast<const char*>(&swept_.vertex_quarters(v));
      __builtin_prefetch(q);
      __builtin_prefetch(q + 64);
    }
  }

  /// The narrow phase of a pair past its volume tests, in the quarters `quarters`: the points
  /// `ids` (VF: vertex, then the face's corners; EE: edge a's ends, then edge b's), the pair
  /// (a, b) as reported.
  /// `known`: the vector filter's result for quarters holding `quarters` (run_queued()), or
  /// kUndecided.
  void narrow(const std::array<std::uint32_t, 4>& ids, std::uint32_t a, std::uint32_t b, ContactKind kind,
              unsigned quarters, WorkerOutput& out, unsigned known = kUndecided) const {
    const bool vf = kind == ContactKind::VertexFace;
    const CcdKind ccd = vf ? CcdKind::VertexFace : CcdKind::EdgeEdge;
    CcdPoints p;
    load(ids, p);
    typename NarrowPhase::Query q;
    unsigned kept;
    if constexpr (std::is_same_v<NarrowPhase, ConservativeCcd>)
      kept = known != kUndecided ? narrow_.filter_known(q, ccd, p, quarters, known) : narrow_.filter(q, ccd, p, quarters);
    else
      kept = narrow_.filter(q, ccd, p, quarters);
    if (!kept) {
      ++(vf ? out.stats.vf_filtered : out.stats.ee_filtered);
      return;
    }
    const RawContact pair{RawContact::make_key(kind, a, b), 0.25 * std::countr_zero(kept), {ids[0], ids[1], ids[2], ids[3]}};
    if (!wanted(pair, out)) return;
    ++(vf ? out.stats.vf_tests : out.stats.ee_tests);
    double toi = 0;
    // The test's time is conservative (never late) but may be earlier than the first quarter
    // kept (with a minimum distance it can be 0 for a pair that meets late in the step); no
    // contact lies before that quarter (the volumes and the filter hold every contact), so
    // the time is raised to its start. Every way of reaching the pair then reports the same
    // time, and an earliest-impact query that skips a pair for its first quarter skips nothing
    // earlier than what it found (the same answer as the full step's, in any order).
    if (narrow_.test(q, ccd, toi, out.stats)) hit(pair, std::max(toi, pair.toi), out);
  }

  /// Whether a pair that passed its volume tests goes to the narrow phase (`pair.toi`: the
  /// start of its first meeting quarter). Earliest queries skip pairs that cannot meet before
  /// the best time found so far; candidate queries collect the pair instead, with that time.
  bool wanted(const RawContact& pair, WorkerOutput& out) const {
    switch (query_.kind()) {
      case StepKind::Full:
      case StepKind::FirstContact:
        return true;
      case StepKind::Earliest:
        return pair.toi < query_.best();
      case StepKind::Candidates:
        out.contacts.push_back(pair);
        return false;
    }
    return true;
  }

  void hit(RawContact c, double toi, WorkerOutput& out) const {
    c.toi = toi;
    out.contacts.push_back(c);
    if (query_.kind() != StepKind::Full) query_.found(toi);
  }

  void load(const std::array<std::uint32_t, 4>& ids, CcdPoints& p) const {
    for (int k = 0; k < 4; ++k) {
      p.start[k] = x0_.point(ids[k]);
      p.end[k] = x1_.point(ids[k]);
    }
  }

  const MeshTopology& topo_;
  const SweptVolumes<BV>& swept_;
  const Positions& x0_;
  const Positions& x1_;
  QueryState& query_;
  NarrowPhase narrow_;
  const Executor* executor_ = nullptr;
};

}  // namespace mccd::detail
