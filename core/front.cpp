#include <mccd/core/front.h>

#include <algorithm>

namespace mccd::detail {

void BvttFront::build(WorkerOutputs& pieces) {
  // A counting sort by first node (stable: the traversal order is kept among nodes of one
  // first node), straight from the pieces in piece order; linear in the front and the BVH.
  std::uint32_t max_a = 0;
  std::size_t n = 0;
  for (const WorkerOutput& o : pieces) {
    n += o.front.size();
    for (const NodePair& p : o.front) max_a = std::max(max_a, p.a);
  }
  std::vector<std::uint32_t> start(std::size_t(max_a) + 2, 0);
  for (const WorkerOutput& o : pieces)
    for (const NodePair& p : o.front) ++start[p.a + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  nodes_.resize(n);
  populate_pages(nodes_.data(), n * sizeof(NodePair));  // written in full, in no order: backed at once
  for (WorkerOutput& o : pieces) {
    for (const NodePair& p : o.front) nodes_[start[p.a]++] = p;
    o.front = std::vector<NodePair>();  // the pieces are not kept
  }
  next_ = LargeVector<NodePair>();
  valid_ = true;
  sprouted_since_build_ = invalidated_since_build_ = 0;
}

void BvttFront::advance(const WorkerOutputs& blocks, std::size_t num_blocks, double sprout_ratio,
                        double invalid_ratio, const Executor& ex) {
  // Reserved once for the blocks together (grown by inserts, a new front's storage faulted in
  // its pages at every growth), with room for a front that grows from step to step; what a
  // new allocation's nodes reach is backed at once. Each block's part then goes to its own
  // place (a serial copy of the whole front was a serial part of every tracked step).
  std::vector<std::size_t> at(num_blocks + 1, 0);
  for (std::size_t b = 0; b < num_blocks; ++b) {
    at[b + 1] = at[b] + blocks[b].front.size();
    sprouted_since_build_ += blocks[b].stats.sprouted;
    invalidated_since_build_ += blocks[b].stats.invalidated;
  }
  const std::size_t n = at[num_blocks];
  next_.clear();
  if (next_.capacity() < n) {
    next_ = LargeVector<NodePair>();
    next_.reserve(n + n / 4);
    populate_pages(next_.data(), n * sizeof(NodePair));
  }
  next_.resize(n);  // left uninitialised (LargeVector): every entry is written below
  ex.dynamic_for(num_blocks, 32, [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b != b1; ++b)
      std::copy(blocks[b].front.begin(), blocks[b].front.end(), next_.begin() + static_cast<std::ptrdiff_t>(at[b]));
  });
  nodes_.swap(next_);
  const double L = static_cast<double>(std::max<std::size_t>(nodes_.size(), 1));
  if (static_cast<double>(sprouted_since_build_) > sprout_ratio * L ||
      static_cast<double>(invalidated_since_build_) > invalid_ratio * L)
    valid_ = false;  // equations 3-4
}

std::size_t BvttFront::cap(WorkerOutputs& units, std::size_t max_bytes) {
  std::size_t held = bytes();
  for (const WorkerOutput& o : units) held += o.front.capacity() * sizeof(NodePair);
  if (max_bytes == 0 || held <= max_bytes) return held;
  // Over the cap: dropped rather than kept and grown; the next step rebuilds it.
  release();
  for (WorkerOutput& o : units) o.front = std::vector<NodePair>();
  return 0;
}

}  // namespace mccd::detail
