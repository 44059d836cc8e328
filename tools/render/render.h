#pragma once
/// @file Headless rendering for `mccd run --image`: a small z-buffer rasteriser, 2x2
/// supersampled, flat shaded with a two-sided light from the camera, dark outlines where depth
/// jumps. Surfaces are grey-blue (one hue per mesh), highlighted triangles red; highlighted
/// triangles hidden behind others show through as a faint red, so that a contact inside a
/// fold stays visible.
#include <vector>

#include "render/camera.h"
#include "render/image.h"
#include "render/scene_view.h"

namespace mccd::cli {

/// Draws `meshes` seen by `camera` into a width x height image. Triangles with a corner
/// behind or too near the camera are left out.
Image render(const std::vector<ViewMesh>& meshes, const Camera& camera, int width, int height);

/// How many pixels of a width x height view (not supersampled) show a highlighted triangle
/// in front of everything else: how well a camera shows the contacts.
std::size_t visible_highlight(const std::vector<ViewMesh>& meshes, const Camera& camera, int width, int height);

}  // namespace mccd::cli
