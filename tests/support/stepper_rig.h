#pragma once
/// @file Test support: a detail::Stepper (parallel/stepper.h) over a generated scene, set up as
/// the public Scene sets it up (its BVH, its topology), stepped frame by frame with any method
/// and step kind; it runs in the calling thread's arena (MCCD_TEST_THREADS applies).
#include <memory>
#include <vector>

#include <mccd/core/scene_topology.h>
#include <mccd/parallel/stepper.h>

#include "fixtures/scenes.h"

namespace mccd::test {

template <BoundingVolume BV>
class StepperRig {
 public:
  StepperRig(const AnimatedScene& s, const SceneOptions& options) : faces_(detail::scene_faces(s.meshes)) {
    for (const auto& frame : s.frames) {
      Positions x;
      for (const Positions& p : frame) x.xyz().insert(x.xyz().end(), p.xyz().begin(), p.xyz().end());
      frames_.push_back(std::move(x));
    }
    topo_ = std::make_unique<detail::SceneTopology>(faces_, options.meshes, resolved_representatives(options));
    BvhTopology bvh = detail::Stepper<BV>::build_bvh(faces_.faces, faces_.face_offsets, options, frames_[0]);
    stepper_ = std::make_unique<detail::Stepper<BV>>(*topo_, options, frames_[0], std::move(bvh));
  }

  std::size_t steps() const { return frames_.size() - 1; }
  /// Step f (frames f -> f + 1); f from 0.
  StepResult step(std::size_t f, Method method, detail::StepKind kind = detail::StepKind::Full) {
    stepper_->start() = frames_[f];
    stepper_->end() = frames_[f + 1];
    return stepper_->step(method, kind);
  }
  detail::Stepper<BV>& stepper() { return *stepper_; }
  std::size_t bvh_size() const { return stepper_->bvh_size(); }

 private:
  detail::SceneFaces faces_;
  std::vector<Positions> frames_;
  std::unique_ptr<detail::SceneTopology> topo_;
  std::unique_ptr<detail::Stepper<BV>> stepper_;
};

}  // namespace mccd::test
