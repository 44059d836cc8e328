#include "progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace mccd::cli {

namespace {
constexpr auto kFirstDraw = std::chrono::milliseconds(1000);  // quick runs never show a bar
constexpr auto kRedraw = std::chrono::milliseconds(200);
constexpr int kBarWidth = 24;
}  // namespace

std::string grouped(std::uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string clock_time(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

bool ProgressBar::stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }

ProgressBar::ProgressBar(bool enabled, std::size_t total)
    : enabled_(enabled), total_(total), start_(std::chrono::steady_clock::now()) {
  if (enabled_) thread_ = std::thread([this] { loop(); });
}

ProgressBar::~ProgressBar() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  erase();
}

void ProgressBar::update(double done, std::size_t contacts) {
  std::lock_guard<std::mutex> lock(mutex_);
  done_ = done;
  contacts_ = contacts;
}

void ProgressBar::print_above(const std::function<void()>& print) {
  std::lock_guard<std::mutex> lock(mutex_);
  const bool was = shown_;
  erase_locked();
  print();
  std::fflush(stdout);
  if (was) draw_locked();
}

void ProgressBar::erase() {
  std::lock_guard<std::mutex> lock(mutex_);
  erase_locked();
}

void ProgressBar::loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (wake_.wait_for(lock, kFirstDraw, [this] { return stopping_; })) return;
  while (!stopping_) {
    draw_locked();
    wake_.wait_for(lock, kRedraw, [this] { return stopping_; });
  }
}

void ProgressBar::draw_locked() {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double frac = total_ ? std::min(1.0, done_ / double(total_)) : 0.0;
  std::string bar(std::size_t(kBarWidth), ' ');
  for (int i = 0; i < int(frac * kBarWidth + 0.5); ++i) bar[std::size_t(i)] = '#';
  const std::string left = done_ > 0 ? clock_time(elapsed / done_ * (double(total_) - done_)) : "?";
  std::fprintf(stderr, "\r\033[K[%s] %zu/%zu steps  contacts %s  elapsed %s  left %s", bar.c_str(),
               std::min(total_, std::size_t(done_)), total_, grouped(contacts_).c_str(), clock_time(elapsed).c_str(),
               left.c_str());
  std::fflush(stderr);
  shown_ = true;
}

void ProgressBar::erase_locked() {
  if (!shown_) return;
  std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  shown_ = false;
}

}  // namespace mccd::cli
