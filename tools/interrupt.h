#pragma once
/// @file Ctrl-C and kill for the `mccd` tool: SIGINT, SIGTERM and SIGHUP are blocked in every
/// thread and taken by one watcher thread, which runs the registered cleanup (finishing output
/// files as the help says: kept and marked incomplete, or removed) under `interrupt_mutex()`,
/// then ends the process by the same signal (the shell sees status 128 + signal number).
/// A step in progress is not waited for: the finished steps are what the files keep.
#include <functional>
#include <mutex>

namespace mccd::cli {

/// Blocks the signals in the calling thread, so every thread started later inherits the
/// mask, and starts the watcher. Call once, first thing in main.
void start_interrupt_watcher();

/// The mutex the cleanup runs under: hold it while changing what the cleanup reads (an
/// output file being written), so that a signal never finds it half-changed.
std::mutex& interrupt_mutex();

/// Registers `fn(signal)` as the cleanup for as long as the guard lives. One at a time.
class InterruptCleanup {
 public:
  explicit InterruptCleanup(std::function<void(int)> fn);
  ~InterruptCleanup();
  InterruptCleanup(const InterruptCleanup&) = delete;
  InterruptCleanup& operator=(const InterruptCleanup&) = delete;
};

}  // namespace mccd::cli
