#pragma once
/// @file Internal: the static data of a scene, independent of the bounding volume. All meshes
/// as one triangle list with global vertex, face and edge ids (each mesh's ids contiguous), its
/// connectivity, the carrier rule and the orphan set.
#include <algorithm>
#include <cstdint>
#include <vector>

#include <mccd/core/canonical_rule_carriers.h>
#include <mccd/core/options.h>
#include <mccd/core/canonical_rule_orphans.h>
#include <mccd/geometry/topology.h>

namespace mccd::detail {

/// All meshes as one triangle list with global vertex ids, and each mesh's first vertex and
/// first face (one more entry: the totals). Cheap; what the BVH build needs, so that it can run
/// beside the connectivity's build (SceneTopology). Throws mccd::Error when the ids do not fit
/// in 32 bits.
struct SceneFaces {
  std::vector<Triangle> faces;
  std::vector<std::size_t> vertex_offsets{0}, face_offsets{0};
};
SceneFaces scene_faces(const std::vector<TriMesh>& meshes);

class SceneTopology {
 public:
  SceneTopology() = default;
  /// From the scene_faces() of validated meshes and their options (empty: defaults). Throws
  /// mccd::Error when the option count is wrong. The carriers and the orphan set are computed
  /// only for the canonical rule; orphan pairs inside a mesh whose own pairs are never tested
  /// are dropped here.
  SceneTopology(const SceneFaces& faces, std::vector<MeshOptions> options,
                Representatives rule = Representatives::Leaf);
  SceneTopology(const SceneTopology&) = delete;  // the carriers point into topo_
  SceneTopology& operator=(const SceneTopology&) = delete;

  const MeshTopology& topology() const { return topo_; }
  /// The representative rule (never Default).
  Representatives representatives() const { return rule_; }
  const Carriers& carriers() const { return carriers_; }
  const OrphanSet& orphans() const { return orphans_; }
  std::size_t num_meshes() const { return vertex_offsets_.size() - 1; }

  const MeshOptions& mesh_options(std::size_t mesh) const { return options_[mesh]; }
  /// Whether any pair of triangles is never tested (a static mesh, or self-collision off).
  bool has_skipped_pairs() const { return has_skipped_; }
  /// Whether pairs between meshes ma and mb are never tested: within one mesh without
  /// self-collision, or between two static meshes.
  bool skips(std::uint32_t ma, std::uint32_t mb) const {
    return ma == mb ? !options_[ma].self_collision : (options_[ma].is_static && options_[mb].is_static);
  }
  bool skips_faces(std::uint32_t f, std::uint32_t g) const {
    return has_skipped_ && skips(mesh_of_face(f), mesh_of_face(g));
  }

  const std::vector<std::size_t>& face_offsets() const { return face_offsets_; }
  /// Index ranges [begin, end) of the vertices of the meshes that move (not static),
  /// neighbouring meshes merged: what a step updates.
  struct Ranges {
    std::vector<std::pair<std::size_t, std::size_t>> vertices;
  };
  const Ranges& moving() const { return moving_; }

  std::size_t vertex_offset(std::size_t mesh) const { return vertex_offsets_[mesh]; }
  std::size_t face_offset(std::size_t mesh) const { return face_offsets_[mesh]; }
  std::size_t edge_offset(std::size_t mesh) const { return edge_offsets_[mesh]; }
  std::uint32_t mesh_of_vertex(std::size_t v) const { return mesh_of(v, vertex_offsets_); }
  std::uint32_t mesh_of_face(std::size_t f) const { return mesh_of(f, face_offsets_); }
  std::uint32_t mesh_of_edge(std::size_t e) const { return mesh_of(e, edge_offsets_); }

 private:
  static std::uint32_t mesh_of(std::size_t id, const std::vector<std::size_t>& offsets) {
    return static_cast<std::uint32_t>(std::upper_bound(offsets.begin(), offsets.end(), id) - offsets.begin() - 1);
  }
  std::vector<std::size_t> vertex_offsets_{0}, face_offsets_{0}, edge_offsets_{0};
  MeshTopology topo_;
  Carriers carriers_;
  OrphanSet orphans_;
  std::vector<MeshOptions> options_;
  Representatives rule_ = Representatives::Leaf;
  bool has_skipped_ = false;
  Ranges moving_;
};

}  // namespace mccd::detail
