#include "render/render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace mccd::cli {

namespace {

constexpr int kSuper = 2;  // samples per pixel along each axis
using Rgb = std::array<float, 3>;
constexpr Rgb kHighlight{0.90f, 0.12f, 0.08f};
constexpr Rgb kPalette[] = {{0.72f, 0.78f, 0.86f}, {0.86f, 0.80f, 0.64f}, {0.70f, 0.84f, 0.72f}, {0.84f, 0.74f, 0.84f}};
static_assert(std::size(kPalette) == kHues);
constexpr float kBehind = 0.38f;   // weight of the highlight seen through a surface
constexpr float kOutline = 0.35f;  // brightness left on an outline

Rgb mix_behind(const Rgb& surface) {
  Rgb c;
  for (int k = 0; k < 3; ++k) c[k] = (1 - kBehind) * surface[k] + kBehind * kHighlight[k];
  return c;
}

Rgb8 to_rgb8(const Rgb& c) {
  auto byte = [](float v) { return std::uint8_t(std::lround(255.0 * std::clamp(v, 0.f, 1.f))); };
  return {byte(c[0]), byte(c[1]), byte(c[2])};
}

/// Camera space: right, up, forward unit vectors; projection to sample coordinates.
struct View {
  Vec3 eye, right, up, forward;
  double focal, cx, cy, near;
  View(const Camera& cam, int w, int h) : eye(cam.eye) {
    forward = (cam.target - cam.eye).normalized();
    Vec3 r = forward.cross(cam.up);
    if (r.norm() < 1e-9) r = forward.cross(std::abs(forward.z()) < 0.9 ? Vec3(0, 0, 1) : Vec3(1, 0, 0));
    right = r.normalized();
    up = right.cross(forward);
    focal = 0.5 * h / std::tan(0.5 * cam.fov_deg * std::numbers::pi / 180.0);
    cx = 0.5 * w;
    cy = 0.5 * h;
    near = 1e-4 * (cam.target - cam.eye).norm();
  }
  /// Sample coordinates and depth along `forward`.
  Vec3 project(const Vec3& p) const {
    const Vec3 d = p - eye;
    const double z = d.dot(forward);
    return {cx + focal * d.dot(right) / z, cy - focal * d.dot(up) / z, z};
  }
};

/// Per-sample buffers: inverse depth of the nearest surface and its face, and inverse depth
/// of the nearest highlighted surface.
struct Buffers {
  int w, h;
  std::vector<float> inv_depth, lit_inv_depth;
  std::vector<std::int32_t> face;
  Buffers(int w_, int h_)
      : w(w_), h(h_), inv_depth(std::size_t(w_) * h_, 0.f), lit_inv_depth(std::size_t(w_) * h_, 0.f),
        face(std::size_t(w_) * h_, -1) {}
};

double edge(const Vec3& a, const Vec3& b, double x, double y) { return (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x()); }

void rasterise(const std::array<Vec3, 3>& s, std::int32_t id, bool lit, Buffers& buf) {
  const double area = edge(s[0], s[1], s[2].x(), s[2].y());
  if (area == 0 || !std::isfinite(area)) return;
  const int x0 = std::max(0, int(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
  const int x1 = std::min(buf.w - 1, int(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
  const int y0 = std::max(0, int(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
  const int y1 = std::min(buf.h - 1, int(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
  const double inv_area = 1.0 / area;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double l0 = edge(s[1], s[2], px, py) * inv_area, l1 = edge(s[2], s[0], px, py) * inv_area;
      const double l2 = 1 - l0 - l1;
      if (l0 < 0 || l1 < 0 || l2 < 0) continue;
      // 1/z is affine in screen space
      const float w = float(l0 / s[0].z() + l1 / s[1].z() + l2 / s[2].z());
      const std::size_t at = std::size_t(y) * buf.w + x;
      if (w > buf.inv_depth[at]) {
        buf.inv_depth[at] = w;
        buf.face[at] = id;
      }
      if (lit && w > buf.lit_inv_depth[at]) buf.lit_inv_depth[at] = w;
    }
}

Rgb shade(const Rgb& base, const Vec3& normal, const View& v, const Vec3& centre) {
  // a light at the camera, a little above and to the left of it: every visible surface lit
  const Vec3 light = (-v.forward + 0.2 * v.up - 0.15 * v.right).normalized();
  const double d = std::abs(normal.dot(light));
  const bool back = normal.dot(v.eye - centre) < 0;
  const double k = (0.45 + 0.50 * d + 0.10 * std::pow(d, 24)) * (back ? 0.88 : 1.0);
  return {float(std::min(1.0, base[0] * k)), float(std::min(1.0, base[1] * k)), float(std::min(1.0, base[2] * k))};
}

/// Rasterises every triangle of `meshes` into `buf`; face ids count over all meshes in order.
void draw(const std::vector<ViewMesh>& meshes, const View& view, Buffers& buf) {
  std::int32_t id = 0;
  for (const ViewMesh& mesh : meshes)
    for (std::size_t f = 0; f < mesh.faces.size(); ++f, ++id) {
      const auto& t = mesh.faces[f];
      const std::array<Vec3, 3> s{view.project(mesh.positions.point(t[0])), view.project(mesh.positions.point(t[1])),
                                  view.project(mesh.positions.point(t[2]))};
      if (s[0].z() < view.near || s[1].z() < view.near || s[2].z() < view.near) continue;
      rasterise(s, id, mesh.highlight[f] != 0, buf);
    }
}

}  // namespace

Rgb8 surface_colour(std::size_t m) { return to_rgb8(kPalette[m % kHues]); }
Rgb8 highlight_colour() { return to_rgb8(kHighlight); }
Rgb8 behind_colour(std::size_t m) { return to_rgb8(mix_behind(kPalette[m % kHues])); }
Rgb8 outline_colour(std::size_t m) {
  const Rgb& p = kPalette[m % kHues];
  return to_rgb8({kOutline * p[0], kOutline * p[1], kOutline * p[2]});
}

std::size_t visible_highlight(const std::vector<ViewMesh>& meshes, const Camera& camera, int width, int height) {
  const View view(camera, width, height);
  Buffers buf(width, height);
  draw(meshes, view, buf);
  std::vector<std::uint8_t> lit;
  for (const ViewMesh& m : meshes) lit.insert(lit.end(), m.highlight.begin(), m.highlight.end());
  std::size_t n = 0;
  for (std::int32_t id : buf.face) n += id >= 0 && lit[std::size_t(id)];
  return n;
}

Image render(const std::vector<ViewMesh>& meshes, const Camera& camera, int width, int height, RenderUse* use) {
  const int w = width * kSuper, h = height * kSuper;
  const View view(camera, w, h);
  Buffers buf(w, h);
  draw(meshes, view, buf);
  // per face: its colour, and its colour with a highlighted triangle behind it (the mix
  // shaded like the surface, so that it reads as a shade of the legend's swatch)
  std::vector<Rgb> colour, colour_behind;
  std::vector<std::uint8_t> face_lit;
  std::vector<std::uint32_t> face_mesh;
  if (use) *use = RenderUse{std::vector<std::size_t>(meshes.size()), 0, std::vector<std::size_t>(meshes.size()), 0};
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const ViewMesh& mesh = meshes[m];
    const Rgb& base = kPalette[m % std::size(kPalette)];
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& t = mesh.faces[f];
      const Vec3 a = mesh.positions.point(t[0]), b = mesh.positions.point(t[1]), c = mesh.positions.point(t[2]);
      Vec3 n = (b - a).cross(c - a);
      n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(-view.forward);
      const bool lit = mesh.highlight[f] != 0;
      colour.push_back(shade(lit ? kHighlight : base, n, view, (a + b + c) / 3));
      colour_behind.push_back(shade(mix_behind(base), n, view, (a + b + c) / 3));
      face_lit.push_back(lit);
      face_mesh.push_back(std::uint32_t(m));
    }
  }
  // resolve each sample, then average kSuper x kSuper samples per pixel
  const double outline = 0.01;  // relative depth jump drawn as an outline
  Image img{width, height, std::vector<std::uint8_t>(3 * std::size_t(width) * height)};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      Rgb sum{0, 0, 0};
      for (int sy = 0; sy < kSuper; ++sy)
        for (int sx = 0; sx < kSuper; ++sx) {
          const int X = x * kSuper + sx, Y = y * kSuper + sy;
          const std::size_t at = std::size_t(Y) * w + X;
          const std::int32_t id = buf.face[at];
          Rgb c;
          if (id < 0) {
            const float g = 0.97f - 0.12f * float(Y) / float(h);
            c = {g, g, g + 0.01f};
          } else {
            const bool lit = face_lit[std::size_t(id)] != 0, behind = !lit && buf.lit_inv_depth[at] > 0;
            c = behind ? colour_behind[std::size_t(id)] : colour[std::size_t(id)];
            // outline: the depth of a neighbour differs a lot, or it is background
            const float z = 1.f / buf.inv_depth[at];
            bool outlined = false;
            for (const std::size_t nb : {X + 1 < w ? at + 1 : at, Y + 1 < h ? at + std::size_t(w) : at}) {
              const float zn = buf.inv_depth[nb] > 0 ? 1.f / buf.inv_depth[nb] : 1e30f;
              if (std::abs(zn - z) > outline * z) {
                for (float& ch : c) ch *= kOutline;
                outlined = true;
              }
            }
            if (use) {
              const std::uint32_t m = face_mesh[std::size_t(id)];
              if (outlined) ++use->outline;
              else if (lit) ++use->highlight;
              else if (behind) ++use->behind[m];
              else ++use->surface[m];
            }
          }
          for (int k = 0; k < 3; ++k) sum[k] += c[k];
        }
      for (int k = 0; k < 3; ++k)
        img.rgb[3 * (std::size_t(y) * width + x) + k] =
            std::uint8_t(std::lround(255.0 * std::clamp(sum[k] / (kSuper * kSuper), 0.f, 1.f)));
    }
  return img;
}

}  // namespace mccd::cli
