#pragma once
/// @file Internal: the coplanarity filter of the broad phase, a necessary condition of contact
/// applied to a feature pair before its elementary test (in the spirit of the deforming
/// non-penetration filters of Tang et al. 2010, this paper's lineage).
///
/// Four points (VF: the vertex and the face's corners; EE: the two edges' ends) can only touch
/// at a time t when they are coplanar at t (within the minimum distance). The coplanarity cubic
/// in Bernstein form over [0, 1], subdivided into the quarters of the step with rigorous error
/// bounds (the arithmetic of geometry/ccd_bernstein.h), tells in which closed quarters that is
/// possible. The broad phase intersects this with the quarters in which the features' swept
/// volumes overlap: a pair with no quarter left cannot touch and never reaches the elementary
/// test.
#include <mccd/geometry/ccd.h>
#include <mccd/geometry/ccd_detail.h>
#include <mccd/geometry/ccd_setup.h>

namespace mccd::detail {

/// The filter and the elementary test of one feature pair, sharing their work: filter() runs
/// the test's stage (b) (the coplanarity cubic with its error bound) and analyses the cubic
/// over the quarters; test() continues from there with stage (c). Stage (a), the swept boxes,
/// is left to the caller's volume tests (the broad phase's quarter volumes are tighter).
class FilteredCcd {
 public:
  /// Bit q (q = 0..3) set when the points may be coplanar (within `min_distance`) at some t
  /// in [q/4, (q+1)/4], among the quarters of `within` (the others are not examined: their
  /// bits are 0). All bits of `within` when the input cannot be analysed (non-finite or out
  /// of the exact scaling range): never clears a quarter it cannot prove empty. `p` must
  /// outlive test().
  unsigned filter(CcdKind kind, const CcdPoints& p, double min_distance, unsigned within = 0xF);
  /// filter() for points whose quarters the vector filter has decided already
  /// (LaneKernels::coplanar_quarters: `known`, its result over quarters holding `within`): the
  /// same return and the same state for test(), without analysing the cubic's quarters again.
  unsigned filter_known(CcdKind kind, const CcdPoints& p, unsigned within, unsigned known);
  /// After filter() returned non-zero: the elementary test of the same points. Whenever their
  /// swept boxes meet (stage (a) passes), the same answer, time of impact and counts as
  /// vertex_face_ccd / edge_edge_ccd on them; otherwise it still never misses a contact.
  bool test(double& toi, CcdCounters* counters);

 private:
  /// Stages (a) and (b) of the points: true when the cubic's quarters are to be analysed;
  /// otherwise `decided` is what filter() returns (0, or every quarter of `within`).
  bool start(CcdKind kind, const CcdPoints& p, double min_distance, unsigned within, unsigned& decided);

  Setup<double> S_;
  const CcdPoints* points_ = nullptr;
  double d_ = 0, toi_ = 0;
  CcdKind kind_ = CcdKind::VertexFace;
  int state_ = 0;  ///< what stages (a) and (b) decided
};

/// FilteredCcd::filter on its own.
inline unsigned coplanar_quarters(CcdKind kind, const CcdPoints& p, double min_distance, unsigned within = 0xF) {
  FilteredCcd f;
  return f.filter(kind, p, min_distance, within);
}

}  // namespace mccd::detail
