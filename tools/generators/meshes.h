#pragma once
/// @file Meshes the generated scenes are built from: surfaces of revolution (spheres, cones,
/// capsules), tubes, and the joining of pieces into one scene mesh.
#include <functional>
#include <utility>
#include <vector>

#include <mccd/geometry/mesh.h>

namespace mccd::gen {

/// A closed surface of revolution about the z axis: a pole at (0, 0, top), rings of
/// `segments` vertices at the (radius, z) points of `profile` (from top to bottom), and a
/// pole at (0, 0, bottom). 2 * segments * profile.size() triangles.
TriMesh make_revolved_mesh(const std::vector<std::pair<double, double>>& profile, int segments, double top, double bottom);
/// A UV sphere of radius r about the origin: `rings` latitude bands.
TriMesh make_uv_sphere(int rings, int segments, double r);
/// A closed cone about the origin (apex up, height h, base radius r), centred on its middle
/// height: apex at z = h/2, base at z = -h/2 (a ring and a centre vertex).
TriMesh make_cone(int segments, double r, double h);
/// A capsule of radius r along z, from z0 to z1 (z0 < z1), `cap_rings` rings per cap.
TriMesh make_capsule(int segments, int cap_rings, int body_rings, double r, double z0, double z1);
/// A tube open at both ends: (rows + 1) rings of `segments` vertices, vertex (row, s) at
/// `at(row, s)`; 2 * rows * segments triangles.
TriMesh make_tube(int rows, int segments, const std::function<Vec3(int row, int s)>& at);

/// Writes `piece`'s vertices turned by `angle` (radians) about the z axis into rows
/// [first, first + piece.num_vertices()) of `scene` (a rigid piece appended earlier).
void place_turned(TriMesh& scene, std::size_t first, const TriMesh& piece, double angle);

/// Appends `piece` to `scene` (a disconnected piece); returns the first vertex of the piece.
std::size_t append_piece(TriMesh& scene, const TriMesh& piece);

}  // namespace mccd::gen
