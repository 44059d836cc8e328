#pragma once
/// @file Headless rendering for `mccd run --image`: a small z-buffer rasteriser, 2x2
/// supersampled, flat shaded with a two-sided light from the camera, dark outlines where depth
/// jumps. Surfaces are grey-blue (one hue per mesh), highlighted triangles red; highlighted
/// triangles hidden behind others show through as a faint red (the surface's hue mixed with
/// red, then shaded), so that a contact inside a fold stays visible.
#include <vector>

#include "render/camera.h"
#include "render/image.h"
#include "render/scene_view.h"

namespace mccd::cli {

/// Which of the renderer's colours a picture shows, counted in samples (2 x 2 per pixel), for
/// its legend.
struct RenderUse {
  std::vector<std::size_t> surface;  ///< per mesh: its surface, in front, not highlighted
  std::size_t highlight = 0;         ///< a highlighted triangle in front
  std::vector<std::size_t> behind;   ///< per mesh: its surface with a highlighted triangle behind it
  std::size_t outline = 0;           ///< darkened where the depth jumps
};

/// The renderer's colours at full light (flat shading makes a surface between about half
/// and all of it): the surface of mesh `m` (one hue per mesh, four hues in turn), a
/// highlighted triangle, a highlighted triangle seen through the surface of mesh `m`, and an
/// outline over mesh `m`.
Rgb8 surface_colour(std::size_t m);
Rgb8 highlight_colour();
Rgb8 behind_colour(std::size_t m);
Rgb8 outline_colour(std::size_t m);
/// How many meshes share a hue: mesh m has the hue of mesh m % kHues.
inline constexpr std::size_t kHues = 4;

/// Draws `meshes` seen by `camera` into a width x height image. Triangles with a corner
/// behind or too near the camera are left out. `use`, when given, receives which colours
/// were drawn.
Image render(const std::vector<ViewMesh>& meshes, const Camera& camera, int width, int height,
             RenderUse* use = nullptr);

/// How many pixels of a width x height view (not supersampled) show a highlighted triangle
/// in front of everything else: how well a camera shows the contacts.
std::size_t visible_highlight(const std::vector<ViewMesh>& meshes, const Camera& camera, int width, int height);

}  // namespace mccd::cli
