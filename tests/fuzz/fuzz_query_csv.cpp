// libFuzzer target: the rational CCD query CSV reader on arbitrary bytes. A refusal must be an
// mccd::Error; accepted queries have finite points and a truth of -1, 0 or 1.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <mccd/geometry/error.h>
#include <mccd/geometry/parsers.h>

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const auto queries =
        mccd::detail::parse_query_csv("fuzz.csv", std::string_view(reinterpret_cast<const char*>(data), size));
    for (const mccd::CcdQuery& q : queries) {
      MCCD_FUZZ_CHECK(q.truth >= -1 && q.truth <= 1);
      for (int i = 0; i < 4; ++i) MCCD_FUZZ_CHECK(q.points.start[i].allFinite() && q.points.end[i].allFinite());
    }
  } catch (const mccd::Error&) {
  }
  return 0;
}
