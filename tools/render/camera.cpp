#include "render/camera.h"

#include "render/render.h"

#include <charconv>
#include <cmath>
#include <numbers>

#include <mccd/geometry/error.h>

namespace mccd::cli {

namespace {

/// Camera directions tried around the target, and the size of the trial renders.
constexpr int kAzimuths = 8, kTrialWidth = 160, kTrialHeight = 120;

std::vector<double> split_numbers(const std::string& text) {
  std::vector<double> out;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    double v = 0;
    const char* b = text.data() + at;
    const char* e = text.data() + comma;
    const auto [ptr, ec] = std::from_chars(b, e, v);
    if (b == e || ptr != e || ec != std::errc() || !std::isfinite(v)) return {};
    out.push_back(v);
    at = comma + 1;
  }
  return out;
}

struct Extent {
  Vec3 min = Vec3::Constant(HUGE_VAL), max = Vec3::Constant(-HUGE_VAL);
  void add(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  Vec3 centre() const { return 0.5 * (min + max); }
  double radius() const { return 0.5 * (max - min).norm(); }
  bool empty() const { return !(max.x() >= min.x()); }
};

}  // namespace

CameraRequest parse_camera(const std::string& text) {
  const std::vector<double> v = split_numbers(text);
  if (v.size() != 3 && v.size() != 6 && v.size() != 9)
    throw Error("--camera: expected EX,EY,EZ (the eye), EX,EY,EZ,TX,TY,TZ (eye and target) or "
                "EX,EY,EZ,TX,TY,TZ,UX,UY,UZ (eye, target and up direction), finite numbers, got '" +
                text.substr(0, 80) + "'");
  CameraRequest r;
  r.eye = Vec3(v[0], v[1], v[2]);
  if (v.size() >= 6) r.target = Vec3(v[3], v[4], v[5]);
  if (v.size() == 9) r.up = Vec3(v[6], v[7], v[8]);
  if (r.target && (*r.target - *r.eye).norm() == 0) throw Error("--camera: the eye and the target are the same point");
  if (r.up && (r.up->norm() == 0 || r.up->cross(*r.target - *r.eye).norm() == 0))
    throw Error("--camera: the up direction must be non-zero and not along the line of sight");
  return r;
}

Vec3 up_axis(const std::vector<ViewMesh>& meshes) {
  Extent scene;
  for (const ViewMesh& m : meshes)
    for (std::size_t v = 0; v < m.positions.rows(); ++v) scene.add(m.positions.point(v));
  if (scene.empty()) return Vec3(0, 0, 1);
  // the axis along which the scene sits most to one side of 0 (a floor at 0, a cloth hanging
  // from a ball), preferring z, then y, on near ties
  int best = 2;
  double best_score = -1;
  for (int k : {2, 1, 0}) {
    const double extent = scene.max[k] - scene.min[k];
    const double score = extent > 0 ? std::abs(scene.max[k] + scene.min[k]) / extent : 0.0;
    if (score > best_score + 0.05) best = k, best_score = score;
  }
  return Vec3::Unit(best);
}

Camera frame_highlight(const std::vector<ViewMesh>& meshes, double aspect, const CameraRequest& request) {
  Extent scene, lit;
  for (const ViewMesh& m : meshes) {
    for (std::size_t v = 0; v < m.positions.rows(); ++v) scene.add(m.positions.point(v));
    for (std::size_t f = 0; f < m.faces.size(); ++f)
      if (m.highlight[f])
        for (std::uint32_t v : m.faces[f]) lit.add(m.positions.point(v));
  }
  Camera cam;
  if (scene.empty()) return cam;
  const Extent& focus = lit.empty() ? scene : lit;
  cam.target = request.target ? *request.target : focus.centre();
  cam.up = request.up ? *request.up : up_axis(meshes);
  if (request.eye) {
    cam.eye = *request.eye;
    return cam;
  }
  const double radius = std::max({focus.radius(), 0.6 * scene.radius(), 1e-9});
  const double half = 0.5 * cam.fov_deg * std::numbers::pi / 180.0;
  const double half_narrow = aspect >= 1 ? half : std::atan(std::tan(half) * aspect);
  const double distance = 1.1 * radius / std::sin(half_narrow);
  const Vec3 e1 = cam.up.unitOrthogonal(), e2 = cam.up.cross(e1);
  // candidate directions around the target; the one showing the most highlighted pixels wins,
  // the first listed on ties (a three-quarter view from 35 degrees above)
  Camera best = cam;
  std::size_t best_score = 0;
  bool first = true;
  for (const double elevation : {35.0, 15.0, 55.0, 75.0, -20.0})
    for (int k = 0; k < kAzimuths; ++k) {
      const double el = elevation * std::numbers::pi / 180.0, az = (2 * k + 1) * std::numbers::pi / kAzimuths;
      Camera c = cam;
      c.eye = cam.target + distance * (std::cos(el) * (std::cos(az) * e1 + std::sin(az) * e2) + std::sin(el) * cam.up);
      const std::size_t score = lit.empty() ? 0 : visible_highlight(meshes, c, kTrialWidth, kTrialHeight);
      if (first || score > best_score) best = c, best_score = score, first = false;
    }
  return best;
}

}  // namespace mccd::cli
