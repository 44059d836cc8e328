#pragma once
/// @file MCCD_ASSERT(condition, message): checks an invariant of the library's own code (not
/// the user's input: bad input gets an mccd::Error). On when MCCD_ENABLE_ASSERTS is defined
/// (CMake defines it in Debug and RelWithDebInfo builds and in sanitizer builds), compiled out
/// otherwise: the condition is then not evaluated. A failed check prints the condition, the
/// message and where, then aborts (a broken invariant means the results cannot be trusted).
#include <cstdio>
#include <cstdlib>

namespace mccd::detail {

[[noreturn]] inline void assert_failed(const char* condition, const char* message, const char* file, int line) {
  std::fprintf(stderr, "mccd: internal check failed: %s (%s) at %s:%d\n", message, condition, file, line);
  std::fflush(stderr);
  std::abort();
}

}  // namespace mccd::detail

#ifdef MCCD_ENABLE_ASSERTS
#define MCCD_ASSERT(condition, message)                                                          \
  do {                                                                                           \
    if (!(condition)) ::mccd::detail::assert_failed(#condition, message, __FILE__, __LINE__); \
  } while (false)
#else
#define MCCD_ASSERT(condition, message) \
  do {                                  \
  } while (false)
#endif
