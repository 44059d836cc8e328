#pragma once
/// @file Internal: the loop a serial algorithm of core/ takes as a parameter where its work may
/// be spread over threads. core/ never starts a thread or a task of its own: the engine
/// (parallel/tbb_executor.h) passes an executor on oneTBB, tests may pass serial_executor().
/// Whatever the executor, an algorithm's result is the same: a body writes only what its own
/// chunk owns.
#include <algorithm>
#include <cstddef>
#include <memory>
#include <type_traits>
#include <utility>

namespace mccd::detail {

/// A non-owning reference to a callable: valid while the callable lives (a loop's body).
template <class Signature>
class FunctionRef;

template <class R, class... Args>
class FunctionRef<R(Args...)> {
 public:
  template <class F>
    requires(!std::is_same_v<std::remove_cvref_t<F>, FunctionRef> && std::is_invocable_r_v<R, F&, Args...>)
  FunctionRef(F&& f) noexcept  // NOLINT: implicit, like a function pointer
      : object_(const_cast<void*>(static_cast<const void*>(std::addressof(f)))),
        call_([](void* o, Args... args) -> R {
          return (*static_cast<std::remove_reference_t<F>*>(o))(std::forward<Args>(args)...);
        }) {}
  R operator()(Args... args) const { return call_(object_, std::forward<Args>(args)...); }

 private:
  void* object_;
  R (*call_)(void*, Args...);
};

/// How a loop's chunks go to threads: fixed equal shares (work of the same cost per item), or
/// handed out as threads free up (uneven work, or a host that stalls a thread now and then).
enum class Schedule { Static, Dynamic };

class Executor {
 public:
  using Chunk = FunctionRef<void(std::size_t begin, std::size_t end)>;
  using Task = FunctionRef<void()>;
  virtual ~Executor() = default;
  /// body(begin, end) over chunks of about `grain` items that cover [0, n) once, possibly
  /// concurrently; n <= grain runs as one chunk on the calling thread. Returns when all ran.
  virtual void for_chunks(std::size_t n, std::size_t grain, Chunk body, Schedule schedule = Schedule::Static) const = 0;
  /// Runs a and b, possibly concurrently; returns when both ran.
  virtual void invoke(Task a, Task b) const = 0;

  void static_for(std::size_t n, std::size_t grain, Chunk body) const { for_chunks(n, grain, body, Schedule::Static); }
  void dynamic_for(std::size_t n, std::size_t grain, Chunk body) const { for_chunks(n, grain, body, Schedule::Dynamic); }
};

/// Everything on the calling thread, in order.
class SerialExecutor final : public Executor {
 public:
  void for_chunks(std::size_t n, std::size_t grain, Chunk body, Schedule = Schedule::Static) const override {
    if (grain == 0) grain = 1;
    for (std::size_t b = 0; b < n; b += grain) body(b, std::min(n, b + grain));
  }
  void invoke(Task a, Task b) const override {
    a();
    b();
  }
};

inline const Executor& serial_executor() {
  static const SerialExecutor serial;
  return serial;
}

}  // namespace mccd::detail
