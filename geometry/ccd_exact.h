#pragma once
/// @file Internal: exact contact predicates of the elementary CCD tests at one instant, on
/// double coordinates, with floating-point expansion arithmetic (error-free two-sum and
/// two-product, Shewchuk-style expansions). Used by geometry/ccd.cpp to certify contacts
/// that touch exactly at t = 0 or t = 1 (where the positions are the input doubles)
/// without bisecting down to the finest time pieces.
///
/// The predicates are certificates: true proves that the primitives touch at that instant
/// (exactly, no rounding); false means "not proved" (no contact, or a degenerate case the
/// predicate does not decide: zero-area face, parallel edges, coordinates too small for
/// the expansions to stay exact). Callers must never treat false as a proof of separation.
#include <array>

#include <mccd/geometry/mesh.h>

namespace mccd::detail {

/// The vertex p touches the closed triangle (a, b, c): p lies in the plane of a non-degenerate
/// triangle and its barycentric coordinates are all >= 0, or p equals a corner.
bool exact_vertex_face_touch(const std::array<Vec3, 4>& pts);

/// The closed segments [a0, a1] and [b0, b1] (pts = {a0, a1, b0, b1}) meet: they are coplanar
/// and not parallel, and the intersection of their lines lies on both, or they share an end.
bool exact_edge_edge_touch(const std::array<Vec3, 4>& pts);

/// Exact sign (-1, 0, +1) of det(b - a, c - a, d - a) for double points (orient3d).
/// Exact for all inputs whose nonzero coordinates lie in [2^-120, 2^120] in magnitude; for
/// other inputs returns 2 (unknown).
int exact_orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace mccd::detail
