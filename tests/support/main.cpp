// Test runner: GoogleTest, with the thread count taken from MCCD_TEST_THREADS when set, so
// the suite runs single-threaded and parallel (the library itself never limits threads).
#include <gtest/gtest.h>
#include <oneapi/tbb/global_control.h>

#include <cstdio>
#include <cstdlib>
#include <memory>

int main(int argc, char** argv) {
  // Each line out as soon as it is written, also into a pipe or a log file: a run that is
  // stopped from outside (a CI time limit) then shows the test it was in.
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  ::testing::InitGoogleTest(&argc, argv);
  std::unique_ptr<tbb::global_control> limit;
  if (const char* env = std::getenv("MCCD_TEST_THREADS")) {
    const int n = std::atoi(env);
    if (n < 1) {
      std::fprintf(stderr, "MCCD_TEST_THREADS must be a positive integer, got '%s'\n", env);
      return 2;
    }
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, n);
  }
  return RUN_ALL_TESTS();
}
