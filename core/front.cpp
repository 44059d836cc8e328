#include <mccd/core/front.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mccd::detail {

void BvttFront::build(WorkerOutputs& pieces, const Executor& ex) {
  // A counting sort by first node (stable: the traversal order is kept among nodes of one
  // first node), straight from the pieces in piece order; linear in the front and the BVH.
  // In parallel over chunks of pieces (runs of pieces of about kChunk nodes or more, at most
  // kMaxChunks, from their sizes only): each chunk counts its nodes by first node; the counts
  // give each chunk its own places, chunk after chunk within a first node; each chunk then
  // writes its nodes there. The same array as one serial pass (which was a long serial part of
  // a step that builds its front).
  constexpr std::size_t kChunk = 8192, kMaxChunks = 16;
  std::size_t n = 0;
  for (const WorkerOutput& o : pieces) n += o.front.size();
  const std::size_t chunk = std::max(kChunk, (n + kMaxChunks - 1) / kMaxChunks);
  std::vector<std::size_t> first{0};  // each chunk's first piece, then the end
  for (std::size_t i = 0, in = 0; i < pieces.size(); ++i) {
    in += pieces[i].front.size();
    if (in >= chunk && i + 1 < pieces.size()) {
      first.push_back(i + 1);
      in = 0;
    }
  }
  first.push_back(pieces.size());
  const std::size_t chunks = first.size() - 1;
  std::vector<std::uint32_t> max_a(chunks, 0);
  ex.dynamic_for(chunks, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c)
      for (std::size_t i = first[c]; i < first[c + 1]; ++i)
        for (const NodePair& p : pieces[i].front) max_a[c] = std::max(max_a[c], p.a);
  });
  const std::size_t firsts = std::size_t(*std::max_element(max_a.begin(), max_a.end())) + 1;
  // at[c * firsts + a]: chunk c's count of first node a, then its next place for one
  std::vector<std::uint32_t> at(chunks * firsts, 0);
  ex.dynamic_for(chunks, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c)
      for (std::size_t i = first[c]; i < first[c + 1]; ++i)
        for (const NodePair& p : pieces[i].front) ++at[c * firsts + p.a];
  });
  std::vector<std::uint32_t> starts(firsts + 1, 0);  // where each first node's nodes start
  ex.static_for(firsts, 4096, [&](std::size_t b, std::size_t e) {
    for (std::size_t a = b; a < e; ++a)
      for (std::size_t c = 0; c < chunks; ++c) starts[a + 1] += at[c * firsts + a];
  });
  for (std::size_t a = 0; a < firsts; ++a) starts[a + 1] += starts[a];
  ex.static_for(firsts, 4096, [&](std::size_t b, std::size_t e) {
    for (std::size_t a = b; a < e; ++a) {
      std::uint32_t next = starts[a];
      for (std::size_t c = 0; c < chunks; ++c) {
        const std::uint32_t count = at[c * firsts + a];
        at[c * firsts + a] = next;
        next += count;
      }
    }
  });
  nodes_.resize(n);
  populate_pages(nodes_.data(), n * sizeof(NodePair));  // written in full, in no order: backed at once
  // The traversal's costly leaf pairs follow their nodes to their places, for the cuts.
  std::vector<std::vector<CostlyNode>> costly_of(chunks);
  std::vector<double> work_of_chunk(chunks, 0);
  ex.dynamic_for(chunks, 1, [&](std::size_t b, std::size_t e) {
    for (std::size_t c = b; c < e; ++c) {
      std::uint32_t* place = at.data() + c * firsts;
      for (std::size_t i = first[c]; i < first[c + 1]; ++i) {
        const WorkerOutput& o = pieces[i];
        work_of_chunk[c] += work_of(o.stats);
        const CostlyNode* next = o.costly.data();
        const CostlyNode* const last = next + o.costly.size();
        for (std::size_t j = 0; j < o.front.size(); ++j) {
          const NodePair& p = o.front[j];
          const std::uint32_t to = place[p.a]++;
          nodes_[to] = p;
          for (; next != last && next->at == j; ++next) costly_of[c].push_back({to, next->work});
        }
      }
    }
  });
  std::vector<CostlyNode> costly;
  double work = 0;
  for (std::size_t c = 0; c < chunks; ++c) {
    costly.insert(costly.end(), costly_of[c].begin(), costly_of[c].end());
    work += work_of_chunk[c];
  }
  std::sort(costly.begin(), costly.end(), [](const CostlyNode& x, const CostlyNode& y) { return x.at < y.at; });
  // The pieces are not kept: thousands of small arrays, released in parallel.
  ex.dynamic_for(pieces.size(), 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) pieces[i].front = std::vector<NodePair>();
  });
  next_ = LargeVector<NodePair>();
  cut({Part{0, n, work, costly}});
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
  std::vector<Part> parts(num_blocks);
  for (std::size_t b = 0; b < num_blocks; ++b)
    parts[b] = {at[b], at[b + 1], work_of(blocks[b].stats), blocks[b].costly};
  cut(parts);
  const double L = static_cast<double>(std::max<std::size_t>(nodes_.size(), 1));
  if (static_cast<double>(sprouted_since_build_) > sprout_ratio * L ||
      static_cast<double>(invalidated_since_build_) > invalid_ratio * L)
    valid_ = false;  // equations 3-4
}

double BvttFront::work_of(const StepStats& s) {
  // In units of about one feature pair's box test (with kNodeWork for each front node, added
  // by cut()): weights fitted to the blocks' times on one thread over the generated scenes
  // (least squares; an elementary test past the lane kernels costs about twelve).
  return 7.0 * double(s.volume_tests) + double(CostlyNode::kLeafPairWork) * double(s.leaf_pairs) +
         double(s.feature_box_tests) + 2.0 * double(s.vf_filtered + s.ee_filtered) +
         12.0 * double(s.vf_tests + s.ee_tests) + 4.0 * double(s.sprouted);
}

void BvttFront::cut(const std::vector<Part>& parts) {
  cuts_.clear();
  const std::size_t n = nodes_.size();
  if (n == 0 || n > std::numeric_limits<std::uint32_t>::max()) return;  // fixed blocks
  double total = 0;
  for (const Part& p : parts) total += p.work + kNodeWork * double(p.end - p.begin);
  const std::size_t block = block_size(n);
  const double target = total / double((n + block - 1) / block);
  const std::size_t longest = 4 * block;
  cuts_.push_back(0);
  std::size_t first = 0;  // the current block's first node
  double work = 0;        // the current block's work so far
  // nodes [i, end) of `each` work apiece join the blocks, cut where a block reaches the target
  // or its most nodes (invariant between runs: work < target, fewer than `longest` nodes)
  auto run = [&](std::size_t i, std::size_t end, double each) {
    while (i < end) {
      const double short_of = (target - work) / each;
      const std::size_t by_work = short_of >= double(end - i)
                                      ? end - i
                                      : std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(short_of)));
      const std::size_t take = std::min({by_work, first + longest - i, end - i});
      i += take;
      work += double(take) * each;
      if (work >= target || i - first >= longest) {
        cuts_.push_back(static_cast<std::uint32_t>(i));
        first = i;
        work = 0;
      }
    }
  };
  for (const Part& p : parts) {
    const std::size_t size = p.end - p.begin;
    if (size == 0) continue;
    double rest = p.work;
    for (const CostlyNode& c : p.costly) rest -= double(c.work);
    const std::size_t plain = size - p.costly.size();
    const double each = (plain > 0 ? std::max(rest, 0.0) / double(plain) : 0.0) + kNodeWork;
    std::size_t i = p.begin;
    for (const CostlyNode& c : p.costly) {
      MCCD_ASSERT(p.begin + c.at >= i && c.at < size, "costly nodes out of order");
      run(i, p.begin + c.at, each);
      run(p.begin + c.at, p.begin + c.at + 1, double(c.work) + kNodeWork);
      i = p.begin + c.at + 1;
    }
    run(i, p.end, each);
  }
  if (first < n) cuts_.push_back(static_cast<std::uint32_t>(n));
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
