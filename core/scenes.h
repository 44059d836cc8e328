#pragma once
/// @file Built-in animated scenes, for the demo, the tests and the benchmarks. Each is a set
/// of meshes and a sequence of frames of their positions; every step (frame i -> i + 1) has
/// genuine collisions, including self-collisions.
#include <string>
#include <vector>

#include "geometry/mesh.h"

namespace mccd {

struct AnimatedScene {
  std::string name;
  std::vector<TriMesh> meshes;                  ///< topology, and frame 0 positions
  std::vector<std::vector<Positions>> frames;   ///< frames[i][m]: positions of mesh m at frame i
  std::size_t num_triangles() const {
    std::size_t n = 0;
    for (auto& m : meshes) n += m.num_faces();
    return n;
  }
};

/// A square cloth of 2 n^2 triangles folding over onto itself along its middle, rippled so
/// that the two halves pass through each other (heavy self-contact).
AnimatedScene make_folding_cloth(int n, int frames);
/// `count` UV spheres pulsating and drifting into each other (inter-object contact).
AnimatedScene make_deforming_spheres(int count, int rings, int frames);
/// `count` unconnected triangles moving randomly in a box (seeded; deterministic).
AnimatedScene make_random_triangles(int count, int frames, unsigned seed = 1);
/// A twisting tube bending into a ring and past it, until its ends pass through each other.
AnimatedScene make_twisting_tube(int rings, int segments, int frames);
/// By name: "cloth", "spheres", "random", "tube"; `size` scales the triangle count
/// (roughly `size` thousand triangles). Throws mccd::Error for an unknown name.
AnimatedScene make_scene(const std::string& name, int size_k, int frames);

}  // namespace mccd
