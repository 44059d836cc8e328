#pragma once
/// @file Internal: the step's contacts. Workers feed a tbb::concurrent_vector in batches (one
/// per block or task, never one record at a time); its order depends on scheduling until the
/// join sorts the contacts into the canonical order, so the result does not. Its segments, like
/// the step's other large buffers, come from the large-array allocator (geometry/
/// large_allocator.h: huge pages for their whole 2 MiB pages): first touched, 4 KiB pages cost
/// a fault each, a large part of a first step on a virtual machine.
#include <vector>

#include <oneapi/tbb/concurrent_vector.h>

#include <mccd/core/contact.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/worker_output.h>

namespace mccd::detail {

using ContactBuffer = tbb::concurrent_vector<RawContact, LargeAllocator<RawContact>>;

/// Moves a worker's contacts into the buffer as one batch, and releases the worker's own
/// storage: a parallel loop has thousands of units, and the next unit a thread runs then reuses
/// the same memory instead of touching new pages (each a fault the first time).
inline void flush(WorkerOutput& out, ContactBuffer& buffer) {
  if (!out.contacts.empty()) buffer.grow_by(out.contacts.begin(), out.contacts.end());
  out.contacts = std::vector<RawContact>();
}

/// The buffer as public contacts (mesh-local ids, EE vertex ids) in the canonical order, their
/// VF / EE counts and the earliest time of impact. Sorted in parallel for large steps, in
/// `scratch` (kept by the caller from step to step, so that its memory is reused).
void join_contacts(const ContactBuffer& buffer, LargeVector<RawContact>& scratch, const SceneTopology& scene,
                   StepResult& result);

}  // namespace mccd::detail
