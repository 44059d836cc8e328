#include <mccd/parallel/step_graph.h>

#include <oneapi/tbb/flow_graph.h>

namespace mccd::detail {

namespace flow = tbb::flow;

struct StepGraph::Impl {
  using Stage = flow::continue_node<flow::continue_msg>;  // runs its stage once all inputs arrived

  explicit Impl(Stages s)
      : stages(std::move(s)),
        update(g, [this](const flow::continue_msg&) { stages.update(); }),
        refit(g, [this](const flow::continue_msg&) { stages.refit(); }),
        search(g, [this](const flow::continue_msg&) { stages.search(); }),
        self(g, [this](const flow::continue_msg&) { stages.self(); }),
        join(g, [this](const flow::continue_msg&) { stages.join(); }) {
    flow::make_edge(update, refit);
    flow::make_edge(refit, search);
    flow::make_edge(refit, self);
    flow::make_edge(search, join);  // join waits for both
    flow::make_edge(self, join);
  }

  Stages stages;
  flow::graph g;
  Stage update, refit, search, self, join;
};

StepGraph::StepGraph(Stages stages) : impl_(std::make_unique<Impl>(std::move(stages))) {}
StepGraph::~StepGraph() = default;

void StepGraph::run() {
  impl_->g.reset();  // attach to the caller's arena; clears what an aborted run left behind
  impl_->update.try_put(flow::continue_msg());
  impl_->g.wait_for_all();
}

}  // namespace mccd::detail
