#include <mccd/parallel/frame_pipeline.h>

#include <oneapi/tbb/flow_graph.h>
#include <oneapi/tbb/task_arena.h>

#include <memory>
#include <mutex>

#include <mccd/geometry/error.h>
#include <mccd/geometry/large_allocator.h>
#include <mccd/parallel/update.h>

namespace mccd {

namespace {
namespace flow = tbb::flow;

struct Frame {
  std::vector<Positions> positions;
};
/// One stepped sub-step on its way to the writer; `last`: the last of its frame interval
/// (its writing frees the frame's place in flight).
struct Stepped {
  PipelineStep step;
  bool last = false;
};
using FramePtr = std::shared_ptr<Frame>;
using SteppedPtr = std::shared_ptr<Stepped>;

std::vector<PositionsView> views(const std::vector<Positions>& p) { return {p.begin(), p.end()}; }

/// out = (1 - u) a + u b, row blocks in parallel (a sub-step's positions: megabytes for a
/// large mesh, written between steps while nothing else runs).
void interpolate(const Positions& a, const Positions& b, double u, Positions& out) {
  out.resize(a.rows());
  const std::size_t n = 3 * a.rows();
  const double *pa = a.xyz().data(), *pb = b.xyz().data();
  double* po = out.xyz().data();
  detail::static_for(n, std::size_t(1) << 15, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i != e; ++i) po[i] = (1 - u) * pa[i] + u * pb[i];
  });
}
}  // namespace

std::size_t run_frame_pipeline(Scene& scene, std::vector<Positions> first, const FrameSource& source,
                               const StepSink& sink, const PipelineOptions& options) {
  if (options.substeps < 1) throw Error("frame pipeline: substeps must be at least 1");
  if (options.frames_in_flight < 1) throw Error("frame pipeline: frames_in_flight must be at least 1");
  std::vector<Positions> prev = std::move(first), cur;
  for (const Positions& p : prev) cur.push_back(detail::backed_copy(p));  // pages backed at once
  // The positions of the sub-step before last, their storage reused for the next sub-step's
  // (a large mesh's arrays fresh every sub-step would fault in their pages every time).
  std::vector<Positions> spare;
  // Contact lists the writer is done with, their storage reused by the next steps (a fresh
  // list every step would touch new pages every time: Scene::step into a StepResult).
  std::mutex lists_mutex;
  std::vector<std::vector<Contact>> lists;
  std::size_t steps = 0;
  const bool one_thread = tbb::this_task_arena::max_concurrency() == 1;

  flow::graph g;
  flow::input_node<FramePtr> reader(g, [&](tbb::flow_control& fc) -> FramePtr {
    auto f = std::make_shared<Frame>();
    if (!source(f->positions)) {
      fc.stop();
      return nullptr;
    }
    return f;
  });
  flow::limiter_node<FramePtr> gate(g, options.frames_in_flight);
  // Written and recycled: the sink, then the list back for a later step.
  auto write = [&](Stepped& s) {
    sink(s.step);
    const std::lock_guard<std::mutex> lock(lists_mutex);
    lists.push_back(std::move(s.step.result.contacts));
  };
  // Each sub-step goes to the writer as soon as it is stepped, so that writing it overlaps
  // the next sub-step. On one thread nothing overlaps (the writer would run only after the
  // frame's last sub-step, and every sub-step's list would be a fresh one): the stepper writes
  // each sub-step itself.
  using StepperNode = flow::multifunction_node<FramePtr, std::tuple<SteppedPtr>>;
  StepperNode stepper(g, flow::serial, [&](const FramePtr& f, StepperNode::output_ports_type& out) {
    const int k_max = options.substeps;
    for (int k = 1; k <= k_max; ++k) {
      const double u = double(k) / k_max;
      std::vector<Positions> end = std::move(spare);
      end.resize(f->positions.size());
      for (std::size_t m = 0; m < end.size(); ++m) {
        if (k < k_max && m < prev.size() && f->positions[m].rows() == prev[m].rows() &&
            cur[m].rows() == prev[m].rows())
          interpolate(cur[m], f->positions[m], u, end[m]);
        else
          end[m] = f->positions[m];
      }
      auto s = std::make_shared<Stepped>();
      s->step.index = ++steps;
      {
        const std::lock_guard<std::mutex> lock(lists_mutex);
        if (!lists.empty()) {
          s->step.result.contacts = std::move(lists.back());
          lists.pop_back();
        }
      }
      // After the first step each starts where the one before ended, the scene's last end:
      // advance() reads and checks only the new end (the same step as step(prev, end)).
      if (s->step.index == 1)
        scene.step(views(prev), views(end), s->step.result, options.method);
      else
        scene.advance(views(end), s->step.result, options.method);
      s->last = k == k_max;
      spare = std::move(prev);
      prev = std::move(end);
      if (!one_thread) {
        std::get<0>(out).try_put(s);
      } else {
        write(*s);
        if (s->last) gate.decrementer().try_put(flow::continue_msg());
      }
    }
    cur = f->positions;
  });
  using WriterNode = flow::multifunction_node<SteppedPtr, std::tuple<flow::continue_msg>>;
  WriterNode writer(g, flow::serial, [&](const SteppedPtr& s, WriterNode::output_ports_type& out) {
    write(*s);
    if (s->last) std::get<0>(out).try_put(flow::continue_msg());
  });

  flow::make_edge(reader, gate);
  flow::make_edge(gate, stepper);
  flow::make_edge(flow::output_port<0>(stepper), writer);
  flow::make_edge(flow::output_port<0>(writer), gate.decrementer());
  reader.activate();
  g.wait_for_all();  // rethrows what a node body threw
  return steps;
}

}  // namespace mccd
