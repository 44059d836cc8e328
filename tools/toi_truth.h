#pragma once
/// @file The exact ground truth of one step in the Time-of-Impact data layout (Belgrod et al.
/// 2023, ../shared/data/README.md): `boxes/<step>{vf,ee}.json` lists candidate pairs
/// `[idA, idB]` of global ids, `mma_bool/<step>{vf,ee}_mma_bool.json` one boolean per pair, in
/// the same order. What `mccd toi-check` checks a step against.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace mccd::cli {

/// One kind's pairs: how many the boxes file lists, and those its truth says collide.
struct TruthPairs {
  std::size_t listed = 0;
  std::vector<std::array<std::uint32_t, 2>> colliding;  ///< in file order, ids as listed
};

/// Parses the two JSON texts (`boxes_name`, `truth_name` name them in messages). Throws
/// mccd::Error naming the file and the entry on invalid JSON, a boxes file that is not an
/// array of `[id, id]` pairs of unsigned integers below 2^32, a truth file that is not an
/// array of booleans, or different lengths.
TruthPairs parse_truth_pairs(std::string_view boxes, const std::string& boxes_name, std::string_view truth,
                             const std::string& truth_name);
/// Reads both files, then parse_truth_pairs (mccd::Error "cannot open" naming the file).
TruthPairs read_truth_pairs(const std::filesystem::path& boxes, const std::filesystem::path& truth);

}  // namespace mccd::cli
