#pragma once
/// @file The camera of the `mccd` renderer, and the automatic framing of highlighted triangles.
#include <optional>
#include <string>
#include <vector>

#include "render/scene_view.h"

namespace mccd::cli {

/// A pinhole camera: where it is, the point it looks at, the world direction that is up in
/// the image, and the vertical field of view in degrees.
struct Camera {
  Vec3 eye = Vec3(0, 0, 1), target = Vec3::Zero(), up = Vec3(0, 1, 0);
  double fov_deg = 30;
};

/// What the user may fix of the camera (`--camera EX,EY,EZ[,TX,TY,TZ[,UX,UY,UZ]]`).
struct CameraRequest {
  std::optional<Vec3> eye, target, up;
};
/// Parses "EX,EY,EZ", "EX,EY,EZ,TX,TY,TZ" or "EX,EY,EZ,TX,TY,TZ,UX,UY,UZ" (finite numbers);
/// throws mccd::Error saying the accepted forms otherwise.
CameraRequest parse_camera(const std::string& text);

/// The scene's up direction when none is given: the positive coordinate axis along which the
/// scene lies most to one side of 0 (a floor at y = 0, a cloth hanging below a ball at z = 0),
/// z on near ties.
Vec3 up_axis(const std::vector<ViewMesh>& meshes);

/// A camera on the highlighted triangles (on the whole scene when none is): aimed at the
/// centre of their bounding box, at a distance that fits them with a margin but shows at least
/// about half the scene around them, from the direction (of 40 tried: 8 around the up axis at
/// 5 elevations) from which the most highlighted pixels are in front; a three-quarter view from
/// 35 degrees above on ties. `request` fixes the eye, the target and the up direction.
/// `aspect` = width / height.
Camera frame_highlight(const std::vector<ViewMesh>& meshes, double aspect, const CameraRequest& request = {});

}  // namespace mccd::cli
