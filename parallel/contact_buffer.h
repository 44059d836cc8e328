#pragma once
/// @file Internal: the step's contacts. Workers feed a tbb::concurrent_vector in batches (one
/// per block or task, never one record at a time); its order depends on scheduling until the
/// join sorts the contacts into the canonical order, so the result does not.
#include <vector>

#include <oneapi/tbb/concurrent_vector.h>

#include <mccd/core/contact.h>
#include <mccd/core/scene_topology.h>
#include <mccd/core/worker_output.h>

namespace mccd::detail {

using ContactBuffer = tbb::concurrent_vector<RawContact>;

/// Moves a worker's contacts into the buffer as one batch.
inline void flush(WorkerOutput& out, ContactBuffer& buffer) {
  if (!out.contacts.empty()) buffer.grow_by(out.contacts.begin(), out.contacts.end());
  out.contacts.clear();
}

/// The buffer as public contacts (mesh-local ids, EE vertex ids) in the canonical order, their
/// VF / EE counts and the earliest time of impact. Sorted in parallel for large steps.
void join_contacts(const ContactBuffer& buffer, const SceneTopology& scene, StepResult& result);

}  // namespace mccd::detail
