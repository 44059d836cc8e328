#include <mccd/core/options.h>

#include <cmath>
#include <cstring>
#include <string>

#include <mccd/core/bvh.h>
#include <mccd/geometry/error.h>

namespace mccd {

namespace {

/// One enum's names: each value with its name, the first entry of a value being the name it
/// is printed as (later ones are accepted aliases).
template <class E>
struct Named {
  E value;
  const char* name;
};

template <class E, std::size_t N>
const char* name_of(const Named<E> (&names)[N], E value) {
  for (const Named<E>& n : names)
    if (n.value == value) return n.name;
  return "?";
}

/// "a, b or c": the names of a table, aliases left out.
template <class E, std::size_t N>
std::string expected_names(const Named<E> (&names)[N]) {
  std::string expected;
  for (std::size_t i = 0; i < N; ++i) {
    if (i > 0 && names[i].value == names[i - 1].value) continue;  // an alias
    bool last = true;
    for (std::size_t k = i + 1; k < N; ++k) last = last && names[k].value == names[i].value;
    expected += expected.empty() ? "" : last ? " or " : ", ";
    expected += names[i].name;
  }
  return expected;
}

/// The value named `name`, or an Error naming `what` and the names expected.
template <class E, std::size_t N>
E parse_named(const Named<E> (&names)[N], const char* name, const char* what) {
  for (const Named<E>& n : names)
    if (!std::strcmp(n.name, name)) return n.value;
  throw Error(std::string("unknown ") + what + " '" + name + "' (expected " + expected_names(names) + ")");
}

/// An Error when `value` (a SceneOptions field `field` of enum type `type`) is none of the
/// table's values.
template <class E, std::size_t N>
void check_named(const Named<E> (&names)[N], E value, const char* field, const char* type) {
  for (const Named<E>& n : names)
    if (n.value == value) return;
  throw Error(std::string("scene options: ") + field + " " + std::to_string(static_cast<unsigned>(value)) +
              " is not a " + type + " (expected " + expected_names(names) + ")");
}

constexpr Named<Method> kMethods[] = {{Method::BruteForce, "bruteforce"},
                                      {Method::Traverse, "traverse"},
                                      {Method::Phc, "phc"},
                                      {Method::Fbd, "fbd"},
                                      {Method::Fbd, "front"}};
constexpr Named<BvhBuild> kBvhBuilds[] = {{BvhBuild::Median, "median"}, {BvhBuild::Sah, "sah"}};
constexpr Named<Representatives> kRepresentatives[] = {{Representatives::Default, "default"},
                                                       {Representatives::Leaf, "leaf"},
                                                       {Representatives::Canonical, "canonical"}};
constexpr Named<VolumeKind> kVolumes[] = {{VolumeKind::Kdop18, "kdop18"}, {VolumeKind::Aabb, "aabb"}};
constexpr Named<VolumeOrder> kVolumeOrders[] = {
    {VolumeOrder::Adaptive, "adaptive"}, {VolumeOrder::First, "first"}, {VolumeOrder::AfterFilter, "after-filter"}};

}  // namespace

const char* to_string(Method m) { return name_of(kMethods, m); }
Method parse_method(const char* name) { return parse_named(kMethods, name, "method"); }
const char* to_string(BvhBuild b) { return name_of(kBvhBuilds, b); }
BvhBuild parse_bvh_build(const char* name) { return parse_named(kBvhBuilds, name, "BVH build"); }
const char* to_string(Representatives r) { return name_of(kRepresentatives, r); }
Representatives parse_representatives(const char* name) {
  return parse_named(kRepresentatives, name, "representative rule");
}
const char* to_string(VolumeKind v) { return name_of(kVolumes, v); }
VolumeKind parse_volume(const char* name) { return parse_named(kVolumes, name, "bounding volume"); }
const char* to_string(VolumeOrder o) { return name_of(kVolumeOrders, o); }
VolumeOrder parse_volume_order(const char* name) { return parse_named(kVolumeOrders, name, "volume order"); }

Representatives resolved_representatives(const SceneOptions& o) {
  if (o.representatives != Representatives::Default) return o.representatives;
  return o.bvh == BvhBuild::Median ? Representatives::Canonical : Representatives::Leaf;
}

void validate(const SceneOptions& o) {
  check_named(kMethods, o.method, "method", "Method");
  check_named(kVolumes, o.volume, "volume", "VolumeKind");
  check_named(kBvhBuilds, o.bvh, "bvh", "BvhBuild");
  check_named(kRepresentatives, o.representatives, "representatives", "Representatives");
  check_named(kVolumeOrders, o.volume_order, "volume_order", "VolumeOrder");
  if (o.leaf_size > BvhTopology::kMaxLeaf)
    throw Error("scene options: leaf_size must be 0 (default) or 1 to 21, got " + std::to_string(o.leaf_size));
  if (!(o.min_distance >= 0) || !std::isfinite(o.min_distance))
    throw Error("scene options: min_distance must be finite and >= 0, got " + std::to_string(o.min_distance));
  if (!(o.rebuild_sprout_ratio > 0) || !(o.rebuild_invalid_ratio > 0))
    throw Error("scene options: rebuild ratios must be > 0, got " + std::to_string(o.rebuild_sprout_ratio) + " and " +
                std::to_string(o.rebuild_invalid_ratio));
}

}  // namespace mccd
