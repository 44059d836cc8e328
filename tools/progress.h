#pragma once
/// @file The progress bar of `mccd run` on a terminal: steps done of all, contacts so far,
/// elapsed and remaining time. Drawn on stderr, only when stderr is a terminal and the run
/// is not --quiet, from the first second on, redrawn a few times a second by its own thread
/// (so the clock moves during a long step). Table rows printed through print_above() appear
/// above the bar.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace mccd::cli {

class ProgressBar {
 public:
  /// `enabled`: draw at all (a terminal and not --quiet); `total`: steps in the run.
  ProgressBar(bool enabled, std::size_t total);
  /// Stops the thread and erases the bar.
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Progress so far: steps done (fractional within a step's sub-steps) and contacts found.
  void update(double done, std::size_t contacts);
  /// Erases the bar, runs `print` (which writes to stdout) and lets the bar come back below.
  void print_above(const std::function<void()>& print);
  /// Erases the bar for good (before the summary, or from the interrupt cleanup).
  void erase();

  /// Whether stderr is a terminal.
  static bool stderr_is_terminal();

 private:
  void loop();
  void draw_locked();
  void erase_locked();

  const bool enabled_;
  const std::size_t total_;
  const std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  std::condition_variable wake_;
  double done_ = 0;
  std::size_t contacts_ = 0;
  bool shown_ = false, stopping_ = false;
  std::thread thread_;
};

/// "1,234,567".
std::string grouped(std::uint64_t n);
/// "0:42", "12:05", "1:02:03".
std::string clock_time(double seconds);

}  // namespace mccd::cli
