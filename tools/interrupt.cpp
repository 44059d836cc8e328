#include "interrupt.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <thread>

namespace mccd::cli {

namespace {

std::function<void(int)>& cleanup() {
  static std::function<void(int)> fn;
  return fn;
}

sigset_t watched() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

void watch(sigset_t set) {
  int sig = 0;
  while (sigwait(&set, &sig) != 0) {
  }
  {
    std::lock_guard<std::mutex> lock(interrupt_mutex());
    if (cleanup()) cleanup()(sig);
    // End by the signal itself, with its default action, still holding the lock so that no
    // other thread touches the files the cleanup finished.
    signal(sig, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    raise(sig);
    _exit(128 + sig);  // not reached: the default action of all three ends the process
  }
}

}  // namespace

std::mutex& interrupt_mutex() {
  static std::mutex m;
  return m;
}

void start_interrupt_watcher() {
  const sigset_t set = watched();
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread(watch, set).detach();
}

InterruptCleanup::InterruptCleanup(std::function<void(int)> fn) {
  std::lock_guard<std::mutex> lock(interrupt_mutex());
  cleanup() = std::move(fn);
}

InterruptCleanup::~InterruptCleanup() {
  std::lock_guard<std::mutex> lock(interrupt_mutex());
  cleanup() = nullptr;
}

}  // namespace mccd::cli
