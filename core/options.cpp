#include <mccd/core/options.h>

#include <cmath>
#include <cstring>
#include <string>

#include <mccd/geometry/error.h>

namespace mccd {

const char* to_string(Method m) {
  switch (m) {
    case Method::BruteForce: return "bruteforce";
    case Method::Traverse: return "traverse";
    case Method::Phc: return "phc";
    case Method::Fbd: return "fbd";
  }
  return "?";
}

Method parse_method(const char* name) {
  if (!std::strcmp(name, "bruteforce")) return Method::BruteForce;
  if (!std::strcmp(name, "traverse")) return Method::Traverse;
  if (!std::strcmp(name, "phc")) return Method::Phc;
  if (!std::strcmp(name, "fbd") || !std::strcmp(name, "front")) return Method::Fbd;
  throw Error(std::string("unknown method '") + name + "' (expected bruteforce, traverse, phc or fbd)");
}

const char* to_string(BvhBuild b) {
  switch (b) {
    case BvhBuild::Median: return "median";
    case BvhBuild::Sah: return "sah";
  }
  return "?";
}

BvhBuild parse_bvh_build(const char* name) {
  if (!std::strcmp(name, "median")) return BvhBuild::Median;
  if (!std::strcmp(name, "sah")) return BvhBuild::Sah;
  throw Error(std::string("unknown BVH build '") + name + "' (expected median or sah)");
}

const char* to_string(Representatives r) {
  switch (r) {
    case Representatives::Default: return "default";
    case Representatives::Leaf: return "leaf";
    case Representatives::Canonical: return "canonical";
  }
  return "?";
}

Representatives parse_representatives(const char* name) {
  if (!std::strcmp(name, "default")) return Representatives::Default;
  if (!std::strcmp(name, "leaf")) return Representatives::Leaf;
  if (!std::strcmp(name, "canonical")) return Representatives::Canonical;
  throw Error(std::string("unknown representative rule '") + name + "' (expected default, leaf or canonical)");
}

Representatives resolved_representatives(const SceneOptions& o) {
  if (o.representatives != Representatives::Default) return o.representatives;
  return o.bvh == BvhBuild::Median ? Representatives::Canonical : Representatives::Leaf;
}

const char* to_string(VolumeKind v) {
  switch (v) {
    case VolumeKind::Kdop18: return "kdop18";
    case VolumeKind::Aabb: return "aabb";
  }
  return "?";
}

VolumeKind parse_volume(const char* name) {
  if (!std::strcmp(name, "kdop18")) return VolumeKind::Kdop18;
  if (!std::strcmp(name, "aabb")) return VolumeKind::Aabb;
  throw Error(std::string("unknown bounding volume '") + name + "' (expected kdop18 or aabb)");
}

void validate(const SceneOptions& o) {
  if (static_cast<unsigned>(o.method) > static_cast<unsigned>(Method::Fbd))
    throw Error("scene options: method " + std::to_string(static_cast<unsigned>(o.method)) +
                " is not a Method (expected bruteforce, traverse, phc or fbd)");
  if (static_cast<unsigned>(o.volume) > static_cast<unsigned>(VolumeKind::Aabb))
    throw Error("scene options: volume " + std::to_string(static_cast<unsigned>(o.volume)) +
                " is not a VolumeKind (expected kdop18 or aabb)");
  if (static_cast<unsigned>(o.bvh) > static_cast<unsigned>(BvhBuild::Sah))
    throw Error("scene options: bvh " + std::to_string(static_cast<unsigned>(o.bvh)) +
                " is not a BvhBuild (expected median or sah)");
  if (static_cast<unsigned>(o.representatives) > static_cast<unsigned>(Representatives::Canonical))
    throw Error("scene options: representatives " + std::to_string(static_cast<unsigned>(o.representatives)) +
                " is not a Representatives (expected default, leaf or canonical)");
  if (o.leaf_size > 16)
    throw Error("scene options: leaf_size must be 0 (default) or 1 to 16, got " + std::to_string(o.leaf_size));
  if (!(o.min_distance >= 0) || !std::isfinite(o.min_distance))
    throw Error("scene options: min_distance must be finite and >= 0, got " + std::to_string(o.min_distance));
  if (!(o.rebuild_sprout_ratio > 0) || !(o.rebuild_invalid_ratio > 0))
    throw Error("scene options: rebuild ratios must be > 0, got " + std::to_string(o.rebuild_sprout_ratio) + " and " +
                std::to_string(o.rebuild_invalid_ratio));
}

}  // namespace mccd
