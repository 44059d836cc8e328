// Ground truth of a Time-of-Impact data set step (see toi_truth.h).
#include "toi_truth.h"

#include <limits>
#include <nlohmann/json.hpp>

#include <mccd/geometry/error.h>
#include <mccd/geometry/text_scan.h>

namespace mccd::cli {

namespace {

nlohmann::json parse_json(std::string_view text, const std::string& name) {
  try {
    return nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {
    throw Error(name + ": invalid JSON: " + e.what());
  }
}

bool is_id(const nlohmann::json& j) {
  return j.is_number_unsigned() && j.get<std::uint64_t>() <= std::numeric_limits<std::uint32_t>::max();
}

}  // namespace

TruthPairs parse_truth_pairs(std::string_view boxes, const std::string& boxes_name, std::string_view truth,
                             const std::string& truth_name) {
  const nlohmann::json b = parse_json(boxes, boxes_name), t = parse_json(truth, truth_name);
  if (!b.is_array()) throw Error(boxes_name + ": expected a JSON array of [id, id] pairs");
  if (!t.is_array()) throw Error(truth_name + ": expected a JSON array of booleans");
  if (b.size() != t.size())
    throw Error(truth_name + ": " + std::to_string(t.size()) + " booleans for " + std::to_string(b.size()) +
                " pairs in " + boxes_name);
  TruthPairs out;
  out.listed = b.size();
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (!b[i].is_array() || b[i].size() != 2 || !is_id(b[i][0]) || !is_id(b[i][1]))
      throw Error(boxes_name + ": pair " + std::to_string(i) + ": expected [id, id] with ids in [0, 2^32)");
    if (!t[i].is_boolean()) throw Error(truth_name + ": entry " + std::to_string(i) + ": expected a boolean");
    if (t[i].get<bool>())
      out.colliding.push_back({static_cast<std::uint32_t>(b[i][0].get<std::uint64_t>()),
                               static_cast<std::uint32_t>(b[i][1].get<std::uint64_t>())});
  }
  return out;
}

TruthPairs read_truth_pairs(const std::filesystem::path& boxes, const std::filesystem::path& truth) {
  const std::string b = detail::read_all(boxes.string()), t = detail::read_all(truth.string());
  return parse_truth_pairs(b, boxes.string(), t, truth.string());
}

}  // namespace mccd::cli
