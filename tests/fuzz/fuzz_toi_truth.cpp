// libFuzzer target: the Time-of-Impact truth reader of `mccd toi-check`. The input is the
// boxes JSON, a NUL byte, then the truth JSON (no NUL: both are the whole input). A refusal
// must be an mccd::Error; accepted truth lists at most as many pairs as the boxes file.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <mccd/geometry/error.h>

#include "fuzz_check.h"
#include "toi_truth.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  const std::size_t nul = all.find('\0');
  const std::string_view boxes = all.substr(0, nul);
  const std::string_view truth = nul == std::string_view::npos ? all : all.substr(nul + 1);
  try {
    const mccd::cli::TruthPairs t = mccd::cli::parse_truth_pairs(boxes, "boxes.json", truth, "truth.json");
    MCCD_FUZZ_CHECK(t.colliding.size() <= t.listed);
  } catch (const mccd::Error&) {
  }
  return 0;
}
