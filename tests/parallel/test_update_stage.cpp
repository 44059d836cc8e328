// What the update leaves for the leaves' lanes (parallel/update.h, core/leaf_lanes.h): after
// every step, each vertex slot's coarse volume is its quarter volumes' on the step's grid, bit
// for bit, also for the slots whose volumes the step keeps (a static mesh's, a resting part's),
// whether the grid is the last step's (their coarse volumes are then not computed again) or a
// new one; and every leaf's lanes, also those kept from the last step by a leaf that repeats
// it, are what a fresh fill writes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

#include <mccd/parallel/stepper.h>

#include "fixtures/scenes.h"
#include "fixtures/shapes.h"
#include "support/bvtt_fixture.h"
#include "support/simd_levels.h"

using namespace mccd;
using namespace mccd::detail;

namespace {

/// Whether the slots' coarse volumes are those of their quarters on the lanes' grid; `first`
/// names the first slot that is not.
bool coarse_volumes_hold(const UpdateState<Kdop18>& st, std::size_t slots, std::size_t& first) {
  const CoarseGrid<9>& grid = st.lanes.grid();
  for (std::size_t s = 0; s < slots; ++s) {
    std::int16_t want[18];
    grid.quantize(st.swept.vertex_quarters_at(static_cast<std::uint32_t>(s)).whole(), want);
    const CoarseDop& got = st.lanes.vertex(static_cast<std::uint32_t>(s));
    for (int k = 0; k < 9; ++k)
      if (got.lo[k] != want[k] || got.hi[k] != want[9 + k]) {
        first = s;
        return false;
      }
  }
  return true;
}

/// Whether every leaf whose lanes are this step's holds what a fresh fill writes from this
/// step's volumes (its vertices', edges' and faces' blocks, its own coarse volume, still());
/// `first` names the first leaf that does not, `checked` counts the leaves compared.
bool lanes_hold(const Stepper<Kdop18>& st, std::uint32_t& first, unsigned& checked) {
  const BvhTopology& bvh = st.bvh();
  const LeafOwnership& owners = st.owners();
  const LeafLanes<Kdop18>& kept = st.volumes().lanes;
  LeafLanes<Kdop18> fresh(bvh, owners);
  fresh.first_touch([](std::size_t n, const auto& body) { body(0, n); });
  fresh.begin(kept.grid());
  fresh.quantize_vertices(0, owners.layout().vertex_slot.size(), st.volumes().swept);
  auto same = [](LeafLanes<Kdop18>::Block a, LeafLanes<Kdop18>::Block b) {
    if (a.n != b.n || a.stride != b.stride) return false;
    for (unsigned r = 0; r < 18; ++r)
      for (unsigned j = 0; j < a.n; ++j)
        if (a.rows[r * a.stride + j] != b.rows[r * b.stride + j]) return false;
    return true;
  };
  for (std::uint32_t n = 0; n < bvh.size(); ++n) {
    if (!bvh.leaf(n) || !kept.filled(n)) continue;
    fresh.ensure(n, bvh, owners, st.node_volumes()[n]);
    ++checked;
    const LeafBlocks k = kept.blocks(n, bvh, owners), f = fresh.blocks(n, bvh, owners);
    const bool ok = same(kept.vertices(n, owners), fresh.vertices(n, owners)) &&
                    same(kept.edges(n, owners), fresh.edges(n, owners)) &&
                    same(kept.faces(n, bvh), fresh.faces(n, bvh)) &&
                    std::memcmp(k.leaf, f.leaf, sizeof(CoarseDop)) == 0 && kept.still(n) == fresh.still(n);
    if (!ok) {
      first = n;
      return false;
    }
  }
  return true;
}

bool same_grid(const CoarseGrid<9>& a, const CoarseGrid<9>& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST(UpdateStage, EverySlotsCoarseVolumeIsOnTheStepsGrid) {
  // A folding cloth whose left half rests (its volumes kept from the second step on), a static
  // copy of it below (kept always); after its frames the cloth flies off in long jumps, so
  // that the grid is made anew while the static copy's volumes are kept. A query on other
  // positions comes between two full steps. At every SIMD level this processor has (the
  // vector update writes the coarse volumes its own way).
  const test::KeepSimdLevel restore;
  for (const LaneKernels* kernels : test::available_levels()) {
    SCOPED_TRACE(to_string(kernels->level));
    select_simd_level(kernels->level);
    const AnimatedScene fold = make_folding_cloth(12, 8);
    AnimatedScene a;
    TriMesh below = fold.meshes[0];
    for (std::size_t v = 0; v < below.vertices.rows(); ++v) below.vertices(v, 2) -= 0.5;
    a.meshes = {fold.meshes[0], below};
    for (const auto& f : fold.frames) a.frames.push_back({f[0], below.vertices});
    for (int jump = 1; jump <= 3; ++jump) {
      Positions far = fold.frames.back()[0];
      for (std::size_t v = 0; v < far.rows(); ++v) far(v, 0) += 4.0 * jump * jump;
      a.frames.push_back({far, below.vertices});
    }
    SceneOptions options;
    options.meshes = {MeshOptions{}, MeshOptions{true, false}};
    SceneFaces faces = scene_faces(a.meshes);
    SceneTopology topo(faces, options.meshes);
    std::vector<Positions> frames;
    for (const auto& f : a.frames) frames.push_back(test::global_positions(f));
    Stepper<Kdop18> stepper(topo, options, frames[0], Stepper<Kdop18>::build_bvh(faces.faces, faces.face_offsets,
                                                                                    options, frames[0]));
    const std::size_t slots = topo.topology().num_vertices();
    unsigned kept_grid = 0, new_grid = 0;
    CoarseGrid<9> last{};
    for (std::size_t f = 0; f + 1 < frames.size(); ++f) {
      if (f == 4) {  // a query: other positions, the same grid or not
        Positions moved = frames[f + 1];
        for (std::size_t v = 0; v < fold.meshes[0].vertices.rows(); ++v) moved(v, 2) += 0.01;
        stepper.start() = frames[f];
        stepper.end() = moved;
        (void)stepper.step(Method::Fbd, StepKind::Earliest);
        std::size_t first = 0;
        EXPECT_TRUE(coarse_volumes_hold(stepper.volumes(), slots, first))
            << "query before step " << f << ", slot " << first;
        last = stepper.volumes().lanes.grid();
      }
      stepper.start() = frames[f];
      stepper.end() = frames[f + 1];
      (void)stepper.step(Method::Fbd, StepKind::Full, f > 0 && f != 4);
      const CoarseGrid<9>& grid = stepper.volumes().lanes.grid();
      if (f > 0) ++(same_grid(grid, last) ? kept_grid : new_grid);
      last = grid;
      std::size_t first = 0;
      EXPECT_TRUE(coarse_volumes_hold(stepper.volumes(), slots, first)) << "step " << f << ", slot " << first;
    }
    EXPECT_GT(kept_grid, 2u);  // steps whose kept slots were not quantized again
    EXPECT_GT(new_grid, 0u);   // and steps where they had to be
  }
}

TEST(LeafLanes, BeginSaysWhetherTheLastUpdatesCoarseVolumesHold) {
  const AnimatedScene fold = make_folding_cloth(6, 2);
  SceneFaces faces = scene_faces(fold.meshes);
  SceneTopology topo(faces, {});
  const Positions x = test::global_positions(fold.frames[0]);
  const BvhTopology bvh(triangle_bounds(faces.faces, x), BvhBuild::Sah, 8, faces.face_offsets, &faces.faces);
  const LeafOwnership owners(bvh, topo.topology());
  LeafLanes<Kdop18> lanes(bvh, owners);
  CoarseGrid<9> g{}, h{};
  for (int s = 0; s < 9; ++s) g.origin[s] = -1, g.scale[s] = 100, h.origin[s] = -2, h.scale[s] = 50;
  EXPECT_FALSE(lanes.begin(g));  // nothing quantized yet
  lanes.vertices_done();
  EXPECT_TRUE(lanes.begin(g));   // the same grid after a completed update
  EXPECT_FALSE(lanes.begin(g));  // the update since the last begin() did not complete
  lanes.vertices_done();
  EXPECT_FALSE(lanes.begin(h));  // another grid
  lanes.vertices_done();
  EXPECT_TRUE(lanes.begin(h));
  h.scale[8] = std::nextafter(h.scale[8], 0.0f);
  EXPECT_FALSE(lanes.begin(h));  // one bit of one slab's scale
}

TEST(LeafLanes, LanesKeptFromTheLastStepAreWhatAFillWrites) {
  // A cloth held still upright on a static one, touching it (a contact in every step, so
  // their leaf pairs are looked at every step and their leaves keep their lanes), a folding
  // cloth beside them, which at the end flies off in long jumps (a new grid: lanes filled
  // again). After every step, each leaf's lanes are what a fresh fill writes.
  const AnimatedScene fold = make_folding_cloth(10, 8);
  TriMesh flat = make_grid_mesh(10, 1.0), upright = make_grid_mesh(10, 1.0);
  double low = 1e9;
  for (std::size_t v = 0; v < upright.vertices.rows(); ++v) low = std::min(low, upright.vertices(v, 1));
  for (std::size_t v = 0; v < upright.vertices.rows(); ++v) {
    // standing on the flat one: its lowest row's vertices lie inside the flat one's triangles
    const Vec3 p = upright.vertices.point(v);
    upright.vertices.set_point(v, Vec3(p.x() + 0.03, 0.01, p.y() - low));
  }
  AnimatedScene a;
  a.meshes = {flat, upright, fold.meshes[0]};
  for (const auto& f : fold.frames) {
    Positions p = f[0];
    for (std::size_t v = 0; v < p.rows(); ++v) p(v, 1) += 3.0;  // beside the others
    a.frames.push_back({flat.vertices, upright.vertices, p});
  }
  for (int jump = 1; jump <= 3; ++jump) {
    Positions far = a.frames.back()[2];
    for (std::size_t v = 0; v < far.rows(); ++v) far(v, 0) += 4.0 * jump * jump;
    a.frames.push_back({flat.vertices, upright.vertices, far});
  }
  for (MeshOptions flat_options : {MeshOptions{true, false}, MeshOptions{}}) {  // static, or held still
    SceneOptions options;
    options.meshes = {flat_options, MeshOptions{}, MeshOptions{}};
    SceneFaces faces = scene_faces(a.meshes);
    SceneTopology topo(faces, options.meshes);
    std::vector<Positions> frames;
    for (const auto& f : a.frames) frames.push_back(test::global_positions(f));
    Stepper<Kdop18> stepper(topo, options, frames[0],
                            Stepper<Kdop18>::build_bvh(faces.faces, faces.face_offsets, options, frames[0]));
    std::size_t contacts = 0;
    for (std::size_t f = 0; f + 1 < frames.size(); ++f) {
      stepper.start() = frames[f];
      stepper.end() = frames[f + 1];
      contacts += stepper.step(Method::Fbd, StepKind::Full, f > 0).contacts.size();
      std::uint32_t leaf = 0;
      unsigned checked = 0;
      EXPECT_TRUE(lanes_hold(stepper, leaf, checked))
          << (flat_options.is_static ? "static" : "still") << ", step " << f << ", leaf " << leaf;
      EXPECT_GT(checked, 0u) << "step " << f;
    }
    EXPECT_GT(contacts, 0u);
  }
}
