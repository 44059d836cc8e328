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

namespace mccd::detail {

/// Bit q (q = 0..3) set when the points may be coplanar (within `min_distance`) at some t in
/// [q/4, (q+1)/4], among the quarters of `within` (the others are not examined: their bits
/// are 0). All bits of `within` when the input cannot be analysed (non-finite or out of the
/// exact scaling range): never clears a quarter it cannot prove empty.
unsigned coplanar_quarters(CcdKind kind, const CcdPoints& p, double min_distance, unsigned within = 0xF);

}  // namespace mccd::detail
