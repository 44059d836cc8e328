#pragma once
/// @file The moment `mccd run --image` / `--colored` shows: the meshes at a time of impact,
/// with the triangles of that sub-step's contacts highlighted, drawn as a PNG or JPEG picture
/// with a key (caption and legend), or written as a PLY with per-face colours.
#include <optional>
#include <string>
#include <vector>

#include <mccd/core/contact.h>
#include <mccd/geometry/mesh.h>

#include "render/camera.h"
#include "render/image.h"
#include "render/key.h"
#include "render/render.h"
#include "render/scene_view.h"

namespace mccd::cli {

/// A sub-step and the contacts it reported; the meshes are shown at its earliest impact.
struct Snapshot {
  std::size_t step = 0, substep = 0;
  int substeps = 1;
  double t = 0;  ///< local time in the sub-step (its earliest impact; 0 when no contact)
  std::vector<Contact> contacts;
};

/// Keeps the snapshot a run will show: the first sub-step with contacts, or with `wanted`
/// set, the first sub-step of that step with contacts (else the step's start).
class SnapshotPicker {
 public:
  SnapshotPicker(std::optional<std::size_t> wanted, int substeps) : wanted_(wanted), substeps_(substeps) {}
  void offer(std::size_t step, std::size_t substep, const StepResult& r);
  /// The chosen snapshot, if any step qualified.
  const std::optional<Snapshot>& chosen() const { return chosen_; }

 private:
  std::optional<std::size_t> wanted_;
  int substeps_;
  std::optional<Snapshot> chosen_;
};

/// The meshes at the snapshot's time, interpolated between frame `step` (`start`) and frame
/// `step` + 1 (`end`), one position array per mesh; triangles touching a contact highlighted
/// (for vertex-face: the face and the triangles around the vertex; for edge-edge: the
/// triangles around both edges).
std::vector<ViewMesh> snapshot_view(const std::vector<TriMesh>& meshes, const std::vector<Positions>& start,
                                    const std::vector<Positions>& end, const Snapshot& snap);

/// The legend of a picture of `view` that shows the colours in `use`: the highlight, the
/// highlight seen through each mesh's surface, each mesh's surface (meshes sharing a hue in
/// one item), the outline; with `use` null, every colour the picture could show.
std::vector<LegendItem> snapshot_legend(const std::vector<ViewMesh>& view, const RenderUse* use);

/// Renders `view` framed automatically or by `camera` into a width x height picture. With a
/// `caption` and room for it (key_height()), a key across the top (render/key.h) holds the
/// caption and the legend of the colours drawn, and the scene is drawn below it; `keyed`,
/// when given, says whether the picture got its key.
Image render_snapshot(const std::vector<ViewMesh>& view, int width, int height, const CameraRequest& camera,
                      const std::vector<std::string>& caption = {}, bool* keyed = nullptr);
/// Writes `view` as one PLY with per-face colours (highlighted red, others by mesh).
void write_snapshot_ply(const std::string& path, const std::vector<ViewMesh>& view);

/// Highlighted triangles in `view`.
std::size_t highlighted_faces(const std::vector<ViewMesh>& view);

}  // namespace mccd::cli
