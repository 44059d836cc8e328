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
  out.queued = std::vector<QueuedPair>();
  out.stack = std::vector<NodePair>();
}

/// The canonical order of n contacts by their keys (unique), as positions into them: `keys`
/// iterates over their keys in sequence; ids in keys are below 2^`id_bits`. Each entry of
/// `order` packs a compact key above the position: entry & ((1 << position_bits(n)) - 1) is the
/// position. When the compact key and the position do not fit in 64 bits, returns false and
/// leaves `order` empty (the caller sorts otherwise). The top bits are distributed serially,
/// the buckets sorted in parallel.
template <class KeyIterator>
bool packed_key_order(KeyIterator keys, std::size_t n, unsigned id_bits, LargeVector<std::uint64_t>& order);
/// Bits that hold a position below n.
inline unsigned position_bits(std::size_t n) { return n > 1 ? static_cast<unsigned>(std::bit_width(n - 1)) : 1u; }

/// What the join keeps from step to step (so that its memory is reused).
struct JoinScratch {
  LargeVector<std::uint64_t> order;
  LargeVector<RawContact> raw;  ///< where keys and positions do not fit one word
};

/// The buffer as public contacts (mesh-local ids, EE vertex ids) in the canonical order, their
/// VF / EE counts and the earliest time of impact. Sorted in parallel for large steps, in
/// `scratch` (kept by the caller from step to step, so that its memory is reused).
/// `allow_packed` false: the record sort always (tests compare the two).
void join_contacts(const ContactBuffer& buffer, JoinScratch& scratch, const SceneTopology& scene, StepResult& result,
                   bool allow_packed = true);

template <class KeyIterator>
bool packed_key_order(KeyIterator keys, std::size_t n, unsigned id_bits, LargeVector<std::uint64_t>& order) {
  order.clear();
  const unsigned pos_bits = position_bits(n), key_bits = 1 + 2 * id_bits, bits = key_bits + pos_bits;
  if (bits > 64) return false;
  // Compact key: kind, a, b (RawContact::make_key's fields, each in id_bits), then the position.
  const std::uint64_t id_mask = (std::uint64_t(1) << id_bits) - 1;
  auto packed = [&](std::uint64_t k, std::size_t i) {
    const std::uint64_t compact = (k >> 63) << (2 * id_bits) | (k >> 32 & id_mask) << id_bits | (k & id_mask);
    return compact << pos_bits | i;
  };
  // The top (up to) 11 bits pick a bucket: a counting pass and a scatter over the keys in
  // sequence, then each bucket sorted on its own.
  const unsigned top = std::min(bits, 11u), shift = bits - top;
  const std::size_t nb = std::size_t(1) << top;
  std::vector<std::uint32_t> start(nb + 1, 0);
  KeyIterator k = keys;
  for (std::size_t i = 0; i < n; ++i, ++k) ++start[(packed(*k, i) >> shift) + 1];
  for (std::size_t b = 0; b < nb; ++b) start[b + 1] += start[b];
  order.resize(n);
  {
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    k = keys;
    for (std::size_t i = 0; i < n; ++i, ++k) {
      const std::uint64_t v = packed(*k, i);
      order[next[v >> shift]++] = v;
    }
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
  };
  if (n > 4096)
    chunked_for(nb, 64, sort_buckets, tbb::auto_partitioner());
  else
    sort_buckets(0, nb);
  return true;
}

}  // namespace mccd::detail
