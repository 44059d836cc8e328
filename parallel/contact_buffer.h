#pragma once
/// @file Internal: the step's contacts. Workers feed a tbb::concurrent_vector in batches (one
/// per block or task, never one record at a time); its order depends on scheduling until the
/// join sorts the contacts into the canonical order, so the result does not. Its segments, like
/// the step's other large buffers, come from the large-array allocator (geometry/
/// large_allocator.h: huge pages from 1 MiB up): first touched, 4 KiB pages cost a fault each,
/// a large part of a first step on a virtual machine.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include <oneapi/tbb/concurrent_vector.h>
#include <oneapi/tbb/parallel_sort.h>
#include <oneapi/tbb/partitioner.h>

#include <mccd/core/contact.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/worker_output.h>
#include <mccd/parallel/tbb_executor.h>

namespace mccd::detail {

using ContactBuffer = tbb::concurrent_vector<RawContact, LargeAllocator<RawContact>>;

/// Moves a worker's contacts into the buffer as one batch, and releases the worker's own
/// scratch storage (its contacts, narrow-phase queue and traversal stack, all empty by then;
/// its front part stays): a parallel loop has thousands of units, and the next unit a thread
/// runs then reuses the same memory instead of touching new pages (each a fault the first
/// time).
inline void flush(WorkerOutput& out, ContactBuffer& buffer) {
  if (!out.contacts.empty()) buffer.grow_by(out.contacts.begin(), out.contacts.end());
  out.contacts = std::vector<RawContact>();
  out.queued = PairQueue();
  out.stack = std::vector<NodePair>();
}

/// The canonical order of n contacts by their keys (unique), as positions into them: `keys`
/// iterates over their keys in sequence (`keys + i` starts at the i-th); ids in keys are below
/// 2^`id_bits`. Each entry of `order` packs a compact key above the position: entry & ((1 <<
/// position_bits(n)) - 1) is the position. When the compact key and the position do not fit in
/// 64 bits, returns false and leaves `order` empty (the caller sorts otherwise). The top bits
/// pick a bucket (counted and scattered by chunks of keys in parallel, each chunk into its own
/// slots of each bucket), then the buckets are sorted in parallel. `counts`: where the
/// per-chunk bucket counts are kept from call to call (a local array when null).
/// `sorted(begin, end)` (optional) is called on each run of `order` as soon as it is final
/// (a group of buckets, inside the same parallel loop that sorted it): a caller that reads the
/// order once saves a loop and finds the entries in cache. `alongside()` (optional) runs once,
/// beside the counting and scattering of a large order (before them for a small one), and
/// always before the first `sorted()`: the caller's own preparation (the result's storage).
template <class KeyIterator, class Sorted, class Alongside>
bool packed_key_order(KeyIterator keys, std::size_t n, unsigned id_bits, LargeVector<std::uint64_t>& order,
                      std::vector<std::uint32_t>* counts, const Sorted& sorted, const Alongside& alongside);
template <class KeyIterator>
bool packed_key_order(KeyIterator keys, std::size_t n, unsigned id_bits, LargeVector<std::uint64_t>& order,
                      std::vector<std::uint32_t>* counts = nullptr) {
  return packed_key_order(keys, n, id_bits, order, counts, [](std::size_t, std::size_t) {}, [] {});
}
/// Bits that hold a position below n.
inline unsigned position_bits(std::size_t n) { return n > 1 ? static_cast<unsigned>(std::bit_width(n - 1)) : 1u; }
/// Contacts from which the join runs in parallel (below, a loop's tasks cost more than they save).
inline constexpr std::size_t kParallelJoin = 1024;

/// Buckets [0, nb) (bucket b's entries at [start[b], start[b + 1]), start ascending) cut into
/// runs of whole buckets of about `share` entries: a run ends with the bucket that brings it
/// to `share` or more, or with the last bucket. The runs' first buckets, then nb.
inline std::vector<std::uint32_t> bucket_runs(const std::uint32_t* start, std::size_t nb, std::size_t share) {
  std::vector<std::uint32_t> runs{0};
  for (std::size_t b = 0, begun = start[0]; b < nb; ++b)
    if (start[b + 1] - begun >= share || b + 1 == nb) {
      runs.push_back(static_cast<std::uint32_t>(b + 1));
      begun = start[b + 1];
    }
  return runs;
}

/// What the join keeps from step to step (so that its memory is reused).
struct JoinScratch {
  LargeVector<std::uint64_t> order;
  std::vector<std::uint32_t> counts;  ///< packed_key_order's per-chunk bucket counts
  LargeVector<RawContact> raw;  ///< where keys and positions do not fit one word
};

/// The buffer as public contacts (mesh-local ids, EE vertex ids) in the canonical order, their
/// VF / EE counts and the earliest time of impact. Sorted in parallel for large steps, in
/// `scratch` (kept by the caller from step to step, so that its memory is reused).
/// `allow_packed` false: the record sort always (tests compare the two). `kept` (a caller's
/// kept result, Scene::step into a StepResult): result.contacts may hold a previous step's
/// list, whose storage is written over when it has room (its pages touched before: no fresh
/// memory, and no initialisation where the old list reaches), and which otherwise grows with a
/// quarter to spare for the next step; without `kept` it is empty and gets exactly its size.
void join_contacts(const ContactBuffer& buffer, JoinScratch& scratch, const SceneTopology& scene, StepResult& result,
                   bool allow_packed = true, bool kept = false);

template <class KeyIterator, class Sorted, class Alongside>
bool packed_key_order(KeyIterator keys, std::size_t n, unsigned id_bits, LargeVector<std::uint64_t>& order,
                      std::vector<std::uint32_t>* counts, const Sorted& sorted, const Alongside& alongside) {
  order.clear();
  const unsigned pos_bits = position_bits(n), key_bits = 1 + 2 * id_bits, bits = key_bits + pos_bits;
  if (bits > 64) {
    alongside();
    return false;
  }
  // Compact key: kind, a, b (RawContact::make_key's fields, each in id_bits), then the position.
  const std::uint64_t id_mask = (std::uint64_t(1) << id_bits) - 1;
  auto packed = [&](std::uint64_t k, std::size_t i) {
    const std::uint64_t compact = (k >> 63) << (2 * id_bits) | (k >> 32 & id_mask) << id_bits | (k & id_mask);
    return compact << pos_bits | i;
  };
  // The top (up to) 11 bits pick a bucket: each chunk of keys counts its buckets, the counts
  // become each chunk's first slot in each bucket (bucket by bucket, chunk by chunk), and each
  // chunk scatters its keys there; then each bucket is sorted on its own. A bucket's entries
  // are the same whatever the chunks, and its sort orders them by their unique keys.
  // Up to 16 chunks of at least 512 keys (a step of a few thousand contacts is still cut up),
  // and 8 or more keys a bucket: the serial pass over the counts (buckets x chunks) stays short.
  const unsigned top = std::min({bits, 11u, std::max(position_bits(n), 7u) - 3}), shift = bits - top;
  const std::size_t nb = std::size_t(1) << top;
  const std::size_t per_chunk =
      n > kParallelJoin ? std::clamp<std::size_t>(n / 16, 512, 16384) : std::max<std::size_t>(n, 1);
  const std::size_t nc = std::max<std::size_t>(1, (n + per_chunk - 1) / per_chunk);
  // Each chunk's counts lie a row of nb + 16 apart: rows a power of two apart (4 KiB or more)
  // all map to the same cache sets, and the serial pass down a column ran 7x slower.
  const std::size_t row = nb + 16;
  std::vector<std::uint32_t> local;
  std::vector<std::uint32_t>& slot = counts ? *counts : local;
  slot.assign(nc * row + nb + 1, 0);
  std::uint32_t* const start = slot.data() + nc * row;
  auto count = [&](std::size_t c) {
    const std::size_t b = c * per_chunk, e = std::min(n, b + per_chunk);
    std::uint32_t* h = slot.data() + c * row;
    KeyIterator k = keys + static_cast<std::ptrdiff_t>(b);
    for (std::size_t i = b; i < e; ++i, ++k) ++h[packed(*k, i) >> shift];
  };
  auto scatter = [&](std::size_t c) {
    const std::size_t b = c * per_chunk, e = std::min(n, b + per_chunk);
    std::uint32_t* next = slot.data() + c * row;
    KeyIterator k = keys + static_cast<std::ptrdiff_t>(b);
    for (std::size_t i = b; i < e; ++i, ++k) {
      const std::uint64_t v = packed(*k, i);
      order[next[v >> shift]++] = v;
    }
  };
  auto place = [&] {
    // Grown with a quarter to spare (a growing step after step would otherwise get fresh
    // memory, pages touched anew, every step), then left uninitialised: every entry is written.
    if (order.capacity() < n) {
      order = LargeVector<std::uint64_t>();
      order.reserve(n + n / 4);
    }
    order.resize(n);
    if (nc > 1)
      for_each_index(nc, count, tbb::simple_partitioner());
    else
      count(0);
    std::uint32_t at = 0;
    for (std::size_t b = 0; b < nb; ++b) {
      start[b] = at;
      for (std::size_t c = 0; c < nc; ++c) {
        const std::uint32_t m = slot[c * row + b];
        slot[c * row + b] = at;
        at += m;
      }
    }
    start[nb] = at;
    if (nc > 1)
      for_each_index(nc, scatter, tbb::simple_partitioner());
    else
      scatter(0);
  };
  if (n > kParallelJoin) {
    invoke_pair(place, alongside);
  } else {
    alongside();
    place();
  }
  // Contacts crowded into a few buckets (all in a small range of ids) would leave one thread
  // sorting most of them: a large bucket is sorted in parallel itself.
  auto sort_buckets = [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b != b1; ++b) {
      const auto first = order.begin() + start[b], last = order.begin() + start[b + 1];
      if (last - first > 32768)
        tbb::parallel_sort(first, last);
      else
        std::sort(first, last);
    }
    if (start[b1] > start[b0]) sorted(start[b0], start[b1]);
  };
  if (n <= kParallelJoin) {
    sort_buckets(0, nb);
    return true;
  }
  // About 64 runs of buckets holding about as many entries each: contacts crowded into a small
  // range of ids fill a few buckets, and runs of as many buckets each left one run most of the
  // sorting.
  const std::vector<std::uint32_t> runs = bucket_runs(start, nb, std::max<std::size_t>(n / 64, 256));
  for_each_index(
      runs.size() - 1, [&](std::size_t r) { sort_buckets(runs[r], runs[r + 1]); }, tbb::auto_partitioner());
  return true;
}

}  // namespace mccd::detail
