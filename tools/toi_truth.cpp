// Ground truth of a Time-of-Impact data set step (see toi_truth.h).
//
// Both files are read as event streams (nlohmann's SAX interface) into flat arrays: a document
// tree of a hundred thousand two-element arrays costs an allocation per array, most of the
// reading time.
#include "toi_truth.h"

#include <algorithm>
#include <limits>
#include <nlohmann/json.hpp>

#include <mccd/geometry/error.h>
#include <mccd/geometry/text_scan.h>

namespace mccd::cli {

namespace {

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

/// One file's top-level array as it streams past: its entries counted, the first malformed
/// one's index kept (`bad`). What is well formed is the subclass's: `scalar` sees each value
/// of an entry (`depth` 1: the entry is that value; 2: an item of an entry that is an array),
/// `entry_ends` keeps an entry and says whether it was well formed. Anything nested deeper,
/// and any object, makes the entry malformed.
class TopArray : public nlohmann::json_sax<nlohmann::json> {
 public:
  bool top_array = false;  ///< the document is an array
  std::size_t entries = 0;
  std::size_t bad = kNone;  ///< the first malformed entry
  std::string parse_error_text;

  bool null() override { return value(Scalar{}); }
  bool boolean(bool b) override { return value(Scalar{Scalar::Bool, b ? 1u : 0u}); }
  bool number_integer(number_integer_t) override { return value(Scalar{}); }  // negative
  bool number_unsigned(number_unsigned_t v) override {
    return value(v <= std::numeric_limits<std::uint32_t>::max() ? Scalar{Scalar::Id, std::uint32_t(v)} : Scalar{});
  }
  bool number_float(number_float_t, const string_t&) override { return value(Scalar{}); }
  bool string(string_t&) override { return value(Scalar{}); }
  bool binary(binary_t&) override { return value(Scalar{}); }
  bool start_object(std::size_t) override { return open(false); }
  bool key(string_t&) override { return true; }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    parse_error_text = e.what();
    return false;
  }

 protected:
  struct Scalar {
    enum Kind { Other, Bool, Id } kind = Other;
    std::uint32_t v = 0;
  };
  /// A scalar at `depth` (1: an entry itself, 2: an item of an entry array).
  virtual void scalar(const Scalar& s, int depth) = 0;
  /// An entry array begins, or an entry ends (`ok`: nothing in it was refused on the way).
  virtual void entry_array_begins() = 0;
  virtual bool entry_ends(bool ok) = 0;
  void refuse() { ok_ = false; }

 private:
  bool value(const Scalar& s) {
    if (depth_ == 0) return true;  // a scalar document: not an array
    if (depth_ == 1) {             // a scalar entry
      ok_ = true;
      scalar(s, 1);
      finish();
      return true;
    }
    if (depth_ == 2 && in_array_) scalar(s, 2);
    return true;
  }
  bool open(bool array) {
    ++depth_;
    if (depth_ == 1) {
      top_array = array;
    } else if (depth_ == 2) {  // an entry that is a container
      ok_ = array;
      in_array_ = array;
      if (array) entry_array_begins();
    } else {
      ok_ = false;  // nothing nests deeper in a well-formed entry
    }
    return true;
  }
  bool close() {
    if (depth_-- == 2) finish();
    return true;
  }
  void finish() {
    if (!entry_ends(ok_) && bad == kNone) bad = entries;
    ++entries;
  }

  int depth_ = 0;
  bool ok_ = true, in_array_ = false;
};

/// The boxes file: `[[id, id], ...]`, ids unsigned below 2^32.
class BoxesReader final : public TopArray {
 public:
  std::vector<std::array<std::uint32_t, 2>> pairs;  ///< one per entry (zeros for a malformed one)

 private:
  void scalar(const Scalar& s, int depth) override {
    if (depth == 1 || s.kind != Scalar::Id || items_ >= 2) {
      refuse();
      return;
    }
    pair_[items_++] = s.v;
  }
  void entry_array_begins() override { items_ = 0; }
  bool entry_ends(bool ok) override {
    ok = ok && items_ == 2;
    pairs.push_back(ok ? pair_ : std::array<std::uint32_t, 2>{0, 0});
    items_ = 0;
    return ok;
  }
  std::array<std::uint32_t, 2> pair_{0, 0};
  unsigned items_ = 0;
};

/// The truth file: `[true, false, ...]`.
class TruthReader final : public TopArray {
 public:
  std::vector<std::uint8_t> values;  ///< one per entry (0 for a malformed one)

 private:
  void scalar(const Scalar& s, int depth) override {
    value_ = depth == 1 && s.kind == Scalar::Bool ? std::int8_t(s.v) : std::int8_t(-1);
  }
  void entry_array_begins() override {}
  bool entry_ends(bool ok) override {
    ok = ok && value_ >= 0;
    values.push_back(ok ? std::uint8_t(value_) : 0);
    value_ = -1;
    return ok;
  }
  std::int8_t value_ = -1;  ///< the entry's boolean, -1 for none (an array entry has none)
};

void read(TopArray& sax, std::string_view text, const std::string& name) {
  if (!nlohmann::json::sax_parse(text.begin(), text.end(), &sax))
    throw Error(name + ": invalid JSON: " + sax.parse_error_text);
}

}  // namespace

TruthPairs parse_truth_pairs(std::string_view boxes, const std::string& boxes_name, std::string_view truth,
                             const std::string& truth_name) {
  BoxesReader b;
  TruthReader t;
  read(b, boxes, boxes_name);
  read(t, truth, truth_name);
  if (!b.top_array) throw Error(boxes_name + ": expected a JSON array of [id, id] pairs");
  if (!t.top_array) throw Error(truth_name + ": expected a JSON array of booleans");
  if (b.entries != t.entries)
    throw Error(truth_name + ": " + std::to_string(t.entries) + " booleans for " + std::to_string(b.entries) +
                " pairs in " + boxes_name);
  // The first malformed entry in file order; the boxes' before the truth's at the same index.
  if (b.bad != kNone && b.bad <= t.bad)
    throw Error(boxes_name + ": pair " + std::to_string(b.bad) + ": expected [id, id] with ids in [0, 2^32)");
  if (t.bad != kNone) throw Error(truth_name + ": entry " + std::to_string(t.bad) + ": expected a boolean");
  TruthPairs out;
  out.listed = b.entries;
  out.colliding.reserve(static_cast<std::size_t>(std::count(t.values.begin(), t.values.end(), 1)));
  for (std::size_t i = 0; i < b.entries; ++i)
    if (t.values[i]) out.colliding.push_back(b.pairs[i]);
  return out;
}

TruthPairs read_truth_pairs(const std::filesystem::path& boxes, const std::filesystem::path& truth) {
  const std::string b = detail::read_all(boxes.string()), t = detail::read_all(truth.string());
  return parse_truth_pairs(b, boxes.string(), t, truth.string());
}

}  // namespace mccd::cli
