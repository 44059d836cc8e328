#include <mccd/core/stats.h>

namespace mccd {

namespace {
void add(CcdCounters& a, const CcdCounters& b) {
  a.queries += b.queries;
  a.box_culled += b.box_culled;
  a.coplanar_culled += b.coplanar_culled;
  a.root_tests += b.root_tests;
  a.fallbacks += b.fallbacks;
  a.hits += b.hits;
  a.fast_hits += b.fast_hits;
  a.fast_misses += b.fast_misses;
  a.pieces += b.pieces;
  a.touches += b.touches;
}
}  // namespace

StepStats& StepStats::operator+=(const StepStats& o) {
  updated_vertices += o.updated_vertices;
  refit_nodes += o.refit_nodes;
  volume_tests += o.volume_tests;
  triangle_tests += o.triangle_tests;
  feature_box_tests += o.feature_box_tests;
  vf_filtered += o.vf_filtered;
  ee_filtered += o.ee_filtered;
  vf_tests += o.vf_tests;
  ee_tests += o.ee_tests;
  add(vf_ccd, o.vf_ccd);
  add(ee_ccd, o.ee_ccd);
  vf_contacts += o.vf_contacts;
  ee_contacts += o.ee_contacts;
  leaf_pairs += o.leaf_pairs;
  adjacent_leaf_pairs += o.adjacent_leaf_pairs;
  repeated_leaf_pairs += o.repeated_leaf_pairs;
  culled_patches += o.culled_patches;
  culled_nodes += o.culled_nodes;
  sprouted += o.sprouted;
  invalidated += o.invalidated;
  rebuilds += o.rebuilds;
  orphan_vf_tested += o.orphan_vf_tested;
  orphan_ee_tested += o.orphan_ee_tested;
  front_size += o.front_size;
  front_bytes += o.front_bytes;
  t_update += o.t_update;
  t_refit += o.t_refit;
  t_front += o.t_front;
  t_self += o.t_self;
  t_contacts += o.t_contacts;
  t_total += o.t_total;
  ws_update += o.ws_update;
  ws_refit += o.ws_refit;
  ws_search += o.ws_search;
  ws_self += o.ws_self;
  ws_branch += o.ws_branch;
  ws_join += o.ws_join;
  ws_input += o.ws_input;
  return *this;
}

double StepStats::staged_work() const {
  return ws_update.work + ws_refit.work + ws_branch.work + ws_join.work + ws_input.work;
}

double StepStats::predicted_seconds(double threads) const {
  const double staged = staged_work();
  const double outside = t_total > staged ? t_total - staged : 0.0;
  return outside + ws_update.predict(threads) + ws_refit.predict(threads) + ws_branch.predict(threads) +
         ws_join.predict(threads) + ws_input.predict(threads);
}

}  // namespace mccd
