#pragma once
/// @file The frame pipeline: a oneTBB flow graph that steps a scene through a sequence of
/// frames while the next frame is being read and the last results are being written.
///
/// Steps are sequential by nature (each needs the previous front and end positions), so the
/// graph overlaps the three stages rather than steps: reading frame i + 1 (I/O, parsing),
/// stepping frame i - 1 -> i (itself parallel inside), and writing step i - 1's contacts.
/// At most `frames_in_flight` frames are held at once.
#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include <mccd/parallel/scene.h>

namespace mccd {

/// One step's output: its number (1-based over all sub-steps) and its result.
struct PipelineStep {
  std::size_t index = 0;
  StepResult result;
};

/// Fills `frame` (one position array per mesh) with the next frame and returns true, or
/// returns false when the sequence ends. Called by one thread at a time, in frame order. May
/// throw; the pipeline then stops and run_frame_pipeline rethrows.
using FrameSource = std::function<bool(std::vector<Positions>& frame)>;
/// Receives each step's output, by one thread at a time, in step order. May throw likewise.
using StepSink = std::function<void(const PipelineStep& step)>;

struct PipelineOptions {
  int substeps = 1;                  ///< linear sub-steps per frame interval (>= 1)
  std::optional<Method> method;      ///< default: the scene's
  std::size_t frames_in_flight = 3;  ///< frames read ahead and not yet written (>= 1)
};

/// Steps `scene` from `first` through every frame of `source`, handing each step's result to
/// `sink`. Returns the number of steps. The results are those of calling scene.step() frame
/// after frame (from the second step on it calls scene.advance(), the same step from the
/// last end: a frame it refuses is named as advance() names it). Runs in the calling thread's
/// arena.
std::size_t run_frame_pipeline(Scene& scene, std::vector<Positions> first, const FrameSource& source,
                               const StepSink& sink, const PipelineOptions& options = {});

}  // namespace mccd
