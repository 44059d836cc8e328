#pragma once
/// @file A position-based cloth (Müller et al. 2007, "Position Based Dynamics"): distance
/// constraints along every mesh edge (stretch) and between the far corners of every two
/// triangles sharing an edge (bending), a collider callback, and a vertex-vertex repulsion
/// that keeps the cloth from passing through itself.
///
/// Determinism: constraints are solved Gauss-Seidel in vertex-disjoint batches (a greedy edge
/// colouring), so each batch runs with tbb::parallel_for and no two constraints of a batch
/// touch the same vertex; the repulsion is computed per vertex from a spatial hash built
/// serially, then applied. The result is bitwise the same on any thread count.
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <mccd/geometry/mesh.h>

namespace mccd::gen {

class PbdCloth {
 public:
  struct Options {
    Vec3 gravity{0, 0, -9.81};  ///< m/s^2
    double stretch = 1.0;       ///< stiffness of the edge constraints per iteration, (0, 1]
    double bend = 0.05;         ///< stiffness of the bending constraints per iteration, [0, 1]
    double damping = 0.3;       ///< velocity lost per second, as a fraction
    /// Two vertices closer than this are pushed apart (the cloth's thickness), unless they lie
    /// on one connected piece less than `2 * repulsion` apart in the rest shape. 0 disables.
    double repulsion = 0.0;
    int iterations = 1;  ///< constraint sweeps per substep
  };
  /// Moves `p` (a vertex's position during a substep) out of the colliders; `x` is where the
  /// vertex was at the substep's start (for friction). Called concurrently for different
  /// vertices.
  using Collider = std::function<void(Vec3& p, const Vec3& x)>;

  /// The cloth at rest in the shape of `mesh` (its positions are the rest and start positions).
  PbdCloth(const TriMesh& mesh, const Options& options);

  std::size_t size() const { return x_.size(); }
  const Vec3& position(std::size_t i) const { return x_[i]; }
  /// Makes vertex i kinematic: it moves only where set_target() puts it.
  void pin(std::size_t i);
  /// Where kinematic vertex i is at the end of the next substep.
  void set_target(std::size_t i, const Vec3& p) { target_[i] = p; }
  /// Adds `dv` to the velocity of every free vertex.
  void add_velocity(const Vec3& dv);

  /// Advances by `dt` seconds: gravity and damping, then the constraint sweeps with the
  /// collider after each, then the repulsion and the collider once more.
  void substep(double dt, const Collider& collide);
  /// Copies the positions into rows [offset, offset + size()) of `out`.
  void write(Positions& out, std::size_t offset = 0) const;

 private:
  struct Constraint {
    std::uint32_t i, j;
    double length, stiffness;
  };
  void build_constraints(const TriMesh& mesh);
  void repel();

  Options opt_;
  std::vector<Vec3> x_, v_, p_, rest_, target_, delta_;
  std::vector<double> w_;               // inverse mass: 1 free, 0 kinematic
  std::vector<std::uint32_t> piece_;    // connected piece of each vertex
  std::vector<std::vector<Constraint>> batches_;
  // spatial hash of the repulsion
  std::vector<std::uint32_t> bucket_start_, bucket_items_;
  std::vector<std::array<std::int32_t, 3>> cell_;
  std::vector<std::uint64_t> key_;
};

}  // namespace mccd::gen
