// libFuzzer target: the OBJ reader on arbitrary bytes. A refusal must be an mccd::Error; an
// accepted mesh must be valid (indices in range, finite coordinates).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include <mccd/geometry/error.h>
#include <mccd/geometry/parsers.h>

#include "fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const mccd::TriMesh m = mccd::detail::parse_obj("fuzz.obj", std::string_view(reinterpret_cast<const char*>(data), size));
    mccd::fuzz::check_mesh(m);
  } catch (const mccd::Error&) {
  }
  return 0;
}
