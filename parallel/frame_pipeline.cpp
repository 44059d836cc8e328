#include <mccd/parallel/frame_pipeline.h>

#include <oneapi/tbb/flow_graph.h>

#include <memory>

#include <mccd/geometry/error.h>

namespace mccd {

namespace {
namespace flow = tbb::flow;

struct Frame {
  std::vector<Positions> positions;
};
struct Batch {
  std::vector<PipelineStep> steps;  // the sub-steps of one frame interval
};
using FramePtr = std::shared_ptr<Frame>;
using BatchPtr = std::shared_ptr<Batch>;

std::vector<PositionsView> views(const std::vector<Positions>& p) { return {p.begin(), p.end()}; }
}  // namespace

std::size_t run_frame_pipeline(Scene& scene, std::vector<Positions> first, const FrameSource& source,
                               const StepSink& sink, const PipelineOptions& options) {
  if (options.substeps < 1) throw Error("frame pipeline: substeps must be at least 1");
  if (options.frames_in_flight < 1) throw Error("frame pipeline: frames_in_flight must be at least 1");
  std::vector<Positions> prev = std::move(first), cur = prev;
  std::size_t steps = 0;

  flow::graph g;
  // reader: the next frame from the source, one at a time (input_node is serial)
  flow::input_node<FramePtr> reader(g, [&](tbb::flow_control& fc) -> FramePtr {
    auto f = std::make_shared<Frame>();
    if (!source(f->positions)) {
      fc.stop();
      return nullptr;
    }
    return f;
  });
  // gate: bounds the frames read ahead of the writer
  flow::limiter_node<FramePtr> gate(g, options.frames_in_flight);
  // stepper: frame i-1 -> i in `substeps` linear sub-steps; serial, since each step needs the last
  flow::function_node<FramePtr, BatchPtr> stepper(g, flow::serial, [&](const FramePtr& f) {
    auto batch = std::make_shared<Batch>();
    const int k_max = options.substeps;
    for (int k = 1; k <= k_max; ++k) {
      const double u = double(k) / k_max;
      std::vector<Positions> end = f->positions;
      if (k < k_max)
        for (std::size_t m = 0; m < end.size() && m < prev.size(); ++m)
          if (end[m].rows() == prev[m].rows()) end[m].mat() = (1 - u) * cur[m].mat() + u * f->positions[m].mat();
      PipelineStep s;
      s.index = ++steps;
      s.result = scene.step(views(prev), views(end), options.method);
      prev = std::move(end);
      batch->steps.push_back(std::move(s));
    }
    cur = f->positions;
    return batch;
  });
  // writer: hands results to the sink in order, then lets the reader go on
  flow::function_node<BatchPtr, flow::continue_msg> writer(g, flow::serial, [&](const BatchPtr& b) {
    for (const PipelineStep& s : b->steps) sink(s);
    return flow::continue_msg();
  });

  flow::make_edge(reader, gate);
  flow::make_edge(gate, stepper);
  flow::make_edge(stepper, writer);
  flow::make_edge(writer, gate.decrementer());
  reader.activate();
  g.wait_for_all();  // rethrows what a node body threw
  return steps;
}

}  // namespace mccd
