#include "run_files.h"

#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include <mccd/geometry/error.h>

namespace mccd::cli {

namespace {

bool has_extension(const std::string& path, const std::string& ext) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e == ext;
}

/// Shortest text that reads back as the same double.
std::string number(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

nlohmann::json facts_json(const std::string& format, const RunFacts& f) {
  return {{"format", format},
          {"version", 1},
          {"input", f.input},
          {"frames", f.frames},
          {"substeps", f.substeps},
          {"method", f.method},
          {"min_distance", f.min_distance},
          {"time", "frame time: a contact in the step from frame F to F + 1 at local time t of sub-step S "
                   "(of K) happened at F + (S + t) / K"}};
}

/// `{...facts..., "NAME": [` : the head of a JSON file whose records follow.
std::string json_head(const nlohmann::json& facts, const std::string& records) {
  std::string head = facts.dump();
  head.pop_back();  // the closing brace: the records and the ending follow
  return head + ",\n\"" + records + "\": [\n";
}

std::string json_ending(std::size_t steps, const std::string& why, const nlohmann::json& extra) {
  nlohmann::json end = extra.is_object() ? extra : nlohmann::json::object();
  end["finished_steps"] = steps;
  end["complete"] = why.empty();
  if (!why.empty()) end["stopped"] = why;
  std::string s = end.dump();
  s.erase(0, 1);  // the opening brace: these fields continue the outer object
  return "\n],\n" + s + "\n";
}

}  // namespace

double frame_time(std::size_t step, std::size_t substep, int substeps, double t) {
  return double(step) + (double(substep) + t) / double(substeps);
}

void check_extension(const std::string& option, const std::string& path, const std::vector<std::string>& extensions) {
  for (const std::string& e : extensions)
    if (has_extension(path, e)) return;
  std::string list;
  for (const std::string& e : extensions) list += (list.empty() ? "" : " or ") + e;
  throw Error(option + " " + path + ": expected a " + list + " file name");
}

void StreamedFile::finish(std::size_t steps, const nlohmann::json& extra) {
  if (done_) return;
  file_.write(ending(steps, "", extra));
  file_.commit();
  done_ = true;
}

void StreamedFile::stop(Partial partial, const std::string& why, std::size_t steps) noexcept {
  if (done_) return;
  done_ = true;
  if (partial == Partial::Remove) {
    file_.abandon();
    return;
  }
  try {
    file_.write(ending(steps, why.empty() ? "stopped" : why, nlohmann::json::object()));
    file_.commit();
  } catch (...) {
    file_.abandon();  // cannot keep it: leave nothing rather than a stray temporary
  }
}

ContactsFile::ContactsFile(const std::string& path, const RunFacts& facts, const std::vector<TriMesh>& meshes)
    : StreamedFile(path), meshes_(meshes), substeps_(facts.substeps), json_(has_extension(path, ".json")) {
  check_extension("--contacts", path, {".csv", ".json"});
  if (json_) {
    nlohmann::json f = facts_json("mccd contacts", facts);
    f["fields"] = "frame, substep: the step from frame F to F + 1, sub-step S; kind: vf (feature_a a vertex, "
                  "feature_b a face) or ee (two edges); vertices: the vertex, then the face's three; or the two "
                  "vertices of each edge; toi: frame time; t: local time in the sub-step";
    file_.write(json_head(f, "contacts"));
  } else {
    file_.write("frame,substep,kind,mesh_a,feature_a,mesh_b,feature_b,v0,v1,v2,v3,toi,t\n");
  }
  file_.flush();
}

void ContactsFile::add(std::size_t step, std::size_t substep, const StepResult& r) {
  std::string out;
  out.reserve(96 * r.contacts.size());
  char buf[256];
  for (const Contact& c : r.contacts) {
    const bool vf = c.kind == ContactKind::VertexFace;
    std::array<std::uint32_t, 4> v{};
    if (vf) {
      const Triangle& f = meshes_[c.mesh_b].faces[c.b];
      v = {c.a, f[0], f[1], f[2]};
    } else {
      v = {c.a_vertices[0], c.a_vertices[1], c.b_vertices[0], c.b_vertices[1]};
    }
    const std::string toi = number(frame_time(step, substep, substeps_, c.toi)), t = number(c.toi);
    if (json_)
      std::snprintf(buf, sizeof buf,
                    "%s{\"frame\":%zu,\"substep\":%zu,\"kind\":\"%s\",\"mesh_a\":%u,\"feature_a\":%u,\"mesh_b\":%u,"
                    "\"feature_b\":%u,\"vertices\":[%u,%u,%u,%u],\"toi\":%s,\"t\":%s}",
                    first_ ? "" : ",\n", step, substep, vf ? "vf" : "ee", c.mesh_a, c.a, c.mesh_b, c.b, v[0], v[1],
                    v[2], v[3], toi.c_str(), t.c_str());
    else
      std::snprintf(buf, sizeof buf, "%zu,%zu,%s,%u,%u,%u,%u,%u,%u,%u,%u,%s,%s\n", step, substep, vf ? "vf" : "ee",
                    c.mesh_a, c.a, c.mesh_b, c.b, v[0], v[1], v[2], v[3], toi.c_str(), t.c_str());
    out += buf;
    first_ = false;
  }
  file_.write(out);
  file_.flush();
}

std::string ContactsFile::ending(std::size_t steps, const std::string& why, const nlohmann::json& extra) const {
  if (json_) return json_ending(steps, why, extra);
  return why.empty() ? std::string() : "# incomplete: " + why + "\n";
}

StatsFile::StatsFile(const std::string& path, const RunFacts& facts) : StreamedFile(path), substeps_(facts.substeps) {
  check_extension("--stats", path, {".json"});
  nlohmann::json f = facts_json("mccd step statistics", facts);
  f["fields"] = "one record per sub-step: contacts; earliest_toi in frame time (null: none); vertices updated and "
                "BVH nodes refitted; bounding-volume, triangle-pair and feature-pair volume test counts, the pairs the "
                "coplanarity filter removed (vf_filtered, ee_filtered; where their own volumes are tested after the "
                "filter, as at leaves that barely move, also pairs whose volumes would not have met) and elementary tests "
                "run (vf_tests, ee_tests); "
                "per-stage elementary test counters; BVTT front size, nodes sprouted and invalidated, rebuilds; orphan "
                "pairs tested; stage times in s";
  file_.write(json_head(f, "steps"));
  file_.flush();
}

void StatsFile::add(std::size_t step, std::size_t substep, const StepResult& r) {
  const StepStats& s = r.stats;
  auto counters = [](const CcdCounters& c) {
    return nlohmann::json{{"queries", c.queries},       {"box_culled", c.box_culled}, {"coplanar_culled", c.coplanar_culled},
                          {"root_tests", c.root_tests}, {"fast_hits", c.fast_hits},   {"fast_misses", c.fast_misses},
                          {"fallbacks", c.fallbacks},   {"pieces", c.pieces},         {"hits", c.hits},
                          {"touches", c.touches}};
  };
  nlohmann::json j = {
      {"frame", step},
      {"substep", substep},
      {"contacts", r.contacts.size()},
      {"vf_contacts", s.vf_contacts},
      {"ee_contacts", s.ee_contacts},
      {"earliest_toi", r.contacts.empty() ? nlohmann::json(nullptr)
                                          : nlohmann::json(frame_time(step, substep, substeps_, r.earliest_toi))},
      {"method", to_string(s.method)},
      {"updated_vertices", s.updated_vertices},
      {"refit_nodes", s.refit_nodes},
      {"volume_tests", s.volume_tests},
      {"triangle_tests", s.triangle_tests},
      {"feature_box_tests", s.feature_box_tests},
      {"vf_filtered", s.vf_filtered},
      {"ee_filtered", s.ee_filtered},
      {"vf_tests", s.vf_tests},
      {"ee_tests", s.ee_tests},
      {"vf_ccd", counters(s.vf_ccd)},
      {"ee_ccd", counters(s.ee_ccd)},
      {"leaf_pairs", s.leaf_pairs},
      {"adjacent_leaf_pairs", s.adjacent_leaf_pairs},
      {"repeated_leaf_pairs", s.repeated_leaf_pairs},
      {"culled_patches", s.culled_patches},
      {"culled_nodes", s.culled_nodes},
      {"front_size", s.front_size},
      {"front_bytes", s.front_bytes},
      {"sprouted", s.sprouted},
      {"invalidated", s.invalidated},
      {"rebuilds", s.rebuilds},
      {"orphan_vf_tested", s.orphan_vf_tested},
      {"orphan_ee_tested", s.orphan_ee_tested},
      {"seconds", {{"update", s.t_update}, {"refit", s.t_refit}, {"front", s.t_front}, {"self", s.t_self},
                   {"contacts", s.t_contacts}, {"total", s.t_total}}}};
  file_.write((first_ ? "" : ",\n") + j.dump());
  first_ = false;
  file_.flush();
}

std::string StatsFile::ending(std::size_t steps, const std::string& why, const nlohmann::json& extra) const {
  return json_ending(steps, why, extra);
}

}  // namespace mccd::cli
