#pragma once
/// @file Helpers for tests of refused input.
#include <functional>
#include <string>

#include <mccd/geometry/error.h>

namespace mccd::test {

/// The message of the mccd::Error `fn` throws ("(no exception)" when none).
inline std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no exception)";
}

}  // namespace mccd::test
