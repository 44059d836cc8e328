#include "snapshot.h"

#include <algorithm>
#include <filesystem>

#include <mccd/geometry/mesh_io.h>

#include "render/render.h"

namespace mccd::cli {

namespace {

/// The faces around each vertex of one mesh, as offsets into one list (CSR).
struct VertexFaces {
  std::vector<std::uint32_t> start, faces;
  explicit VertexFaces(const TriMesh& m) : start(m.num_vertices() + 1, 0) {
    for (const Triangle& t : m.faces)
      for (std::uint32_t v : t) ++start[v + 1];
    for (std::size_t v = 0; v < m.num_vertices(); ++v) start[v + 1] += start[v];
    faces.resize(start.back());
    std::vector<std::uint32_t> at(start.begin(), start.end() - 1);
    for (std::size_t f = 0; f < m.faces.size(); ++f)
      for (std::uint32_t v : m.faces[f]) faces[at[v]++] = std::uint32_t(f);
  }
  template <class F>
  void each(std::uint32_t v, F&& f) const {
    for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) f(faces[i]);
  }
};

}  // namespace

void SnapshotPicker::offer(std::size_t step, std::size_t substep, const StepResult& r) {
  if (chosen_ && !(wanted_ && chosen_->step == *wanted_ && chosen_->contacts.empty())) return;
  if (wanted_ && step != *wanted_) return;
  if (r.contacts.empty()) {
    if (wanted_ && !chosen_) chosen_ = Snapshot{step, 0, substeps_, 0.0, {}};  // the step's start, unless a contact comes
    return;
  }
  chosen_ = Snapshot{step, substep, substeps_, r.earliest_toi, r.contacts};
}

std::vector<ViewMesh> snapshot_view(const std::vector<TriMesh>& meshes, const std::vector<Positions>& start,
                                    const std::vector<Positions>& end, const Snapshot& snap) {
  const double u = (double(snap.substep) + snap.t) / double(snap.substeps);
  std::vector<ViewMesh> view(meshes.size());
  std::vector<VertexFaces> around;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    view[m].name = meshes[m].name;
    view[m].faces = meshes[m].faces;
    view[m].positions = start[m];
    view[m].positions.mat() = (1 - u) * start[m].mat() + u * end[m].mat();
    view[m].highlight.assign(meshes[m].faces.size(), 0);
    around.emplace_back(meshes[m]);
  }
  auto edge_faces = [&](std::uint32_t mesh, const std::array<std::uint32_t, 2>& e) {
    around[mesh].each(e[0], [&](std::uint32_t f) {
      const Triangle& t = meshes[mesh].faces[f];
      if (std::find(t.begin(), t.end(), e[1]) != t.end()) view[mesh].highlight[f] = 1;
    });
  };
  for (const Contact& c : snap.contacts) {
    if (c.kind == ContactKind::VertexFace) {
      view[c.mesh_b].highlight[c.b] = 1;
      around[c.mesh_a].each(c.a, [&](std::uint32_t f) { view[c.mesh_a].highlight[f] = 1; });
    } else {
      edge_faces(c.mesh_a, c.a_vertices);
      edge_faces(c.mesh_b, c.b_vertices);
    }
  }
  return view;
}

std::size_t highlighted_faces(const std::vector<ViewMesh>& view) {
  std::size_t n = 0;
  for (const ViewMesh& m : view) n += std::size_t(std::count(m.highlight.begin(), m.highlight.end(), 1));
  return n;
}

std::vector<LegendItem> snapshot_legend(const std::vector<ViewMesh>& view, const RenderUse* use) {
  const bool lit = highlighted_faces(view) > 0;
  auto shows = [&](const std::vector<std::size_t> RenderUse::*counts, std::size_t m) {
    return use ? (use->*counts)[m] > 0 : true;
  };
  std::vector<LegendItem> legend;
  if (use ? use->highlight > 0 : lit) legend.push_back({{highlight_colour()}, "triangles of the contacts shown"});
  // seen through a surface: one swatch per hue it shows over
  LegendItem behind{{}, "the same, behind a surface"};
  for (std::size_t hue = 0; hue < kHues && lit; ++hue)
    for (std::size_t m = hue; m < view.size(); m += kHues)
      if (shows(&RenderUse::behind, m)) {
        behind.swatches.push_back(behind_colour(hue));
        break;
      }
  if (!behind.swatches.empty()) legend.push_back(behind);
  // the surfaces: one item per hue, naming its meshes
  for (std::size_t hue = 0; hue < kHues; ++hue) {
    std::vector<std::string> names;
    for (std::size_t m = hue; m < view.size(); m += kHues)
      if (shows(&RenderUse::surface, m))
        names.push_back(view[m].name.empty() ? "mesh " + std::to_string(m)
                                             : std::filesystem::path(view[m].name).filename().string());
    if (names.empty()) continue;
    std::string label = view.size() == 1 ? "surface" : names[0];
    for (std::size_t i = 1; i < names.size() && i < 3; ++i) label += ", " + names[i];
    if (names.size() > 3) label += ", ... (" + std::to_string(names.size()) + " meshes)";
    legend.push_back({{surface_colour(hue)}, label});
  }
  if (use ? use->outline > 0 : !view.empty()) legend.push_back({{outline_colour(0)}, "outline (a jump in depth)"});
  return legend;
}

Image render_snapshot(const std::vector<ViewMesh>& view, int width, int height, const CameraRequest& camera,
                      const std::vector<std::string>& caption, bool* keyed) {
  // the band is sized for every colour the picture could show; the legend lists those shown
  PictureKey key{caption, snapshot_legend(view, nullptr)};
  const int band = caption.empty() ? 0 : key_height(key, width, height);
  if (keyed) *keyed = band > 0;
  const Camera cam = frame_highlight(view, double(width) / double(height - band), camera);
  RenderUse use;
  const Image scene = render(view, cam, width, height - band, &use);
  if (band == 0) return scene;
  key.legend = snapshot_legend(view, &use);
  Image out{width, height, std::vector<std::uint8_t>(3 * std::size_t(width) * std::size_t(height))};
  std::copy(scene.rgb.begin(), scene.rgb.end(), out.rgb.begin() + std::ptrdiff_t(3 * std::size_t(width) * std::size_t(band)));
  draw_key(out, key, band);
  return out;
}

void write_snapshot_ply(const std::string& path, const std::vector<ViewMesh>& view) {
  static const std::array<std::uint8_t, 3> kLit{230, 30, 20};
  static const std::array<std::array<std::uint8_t, 3>, 4> kPalette{{{184, 199, 219}, {219, 204, 163}, {178, 214, 184}, {214, 189, 214}}};
  TriMesh all;
  all.name = path;
  FaceColors colours;
  for (std::size_t m = 0; m < view.size(); ++m) {
    const auto offset = std::uint32_t(all.vertices.rows());
    all.vertices.xyz().insert(all.vertices.xyz().end(), view[m].positions.xyz().begin(), view[m].positions.xyz().end());
    for (std::size_t f = 0; f < view[m].faces.size(); ++f) {
      const Triangle& t = view[m].faces[f];
      all.faces.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
      colours.push_back(view[m].highlight[f] ? kLit : kPalette[m % kPalette.size()]);
    }
  }
  write_ply(path, all, colours);
}

}  // namespace mccd::cli
