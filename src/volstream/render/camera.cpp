#include "volstream/render/camera.h"

#include <algorithm>
#include <cmath>

#include "volstream/core/error.h"

namespace vs {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

Camera default_camera(const Box3<double>& box, double aspect) {
  Camera c;
  const vec3d centre = box.center();
  // Front-right-above diagonal: sees three faces of the box.
  const vec3d back = normalize(vec3d(0.45, 0.5, 1.0));  // from the centre towards the camera
  const vec3d fwd = -back;
  const vec3d right = normalize(cross(fwd, c.up));
  const vec3d up = cross(right, fwd);
  // Nearest distance at which all 8 corners project inside the image (with a 6% margin).
  const double tan_v = 0.94 * std::tan(0.5 * c.fov_deg * kPi / 180.0);
  const double tan_h = tan_v * std::max(aspect, 1e-3);
  double dist = 0;
  for (int k = 0; k < 8; ++k) {
    const vec3d corner((k & 1 ? box.upper : box.lower).x, (k & 2 ? box.upper : box.lower).y,
                       (k & 4 ? box.upper : box.lower).z);
    const vec3d q = corner - centre;
    const double depth = dot(q, fwd);  // corner lies this much further away than the centre
    dist = std::max({dist, std::fabs(dot(q, right)) / tan_h - depth, std::fabs(dot(q, up)) / tan_v - depth});
  }
  c.position = centre + back * std::max(dist, 0.51 * length(box.size()));  // outside the box
  c.look_at = centre;
  return c;
}

CameraView make_camera_view(const Camera& cam, uint32_t width, uint32_t height) {
  if (width == 0 || height == 0) throw UsageError("image size must be positive");
  const vec3d fwd_raw = cam.look_at - cam.position;
  const double dist = length(fwd_raw);
  if (!(dist > 0) || !std::isfinite(dist)) throw UsageError("camera position and look-at point must differ");
  const vec3d fwd = fwd_raw / dist;
  const vec3d right_raw = cross(fwd, cam.up);
  if (!(length(right_raw) > 1e-9 * length(cam.up)))
    throw UsageError("camera up vector is parallel to the view direction");
  const vec3d right = normalize(right_raw);
  const vec3d up = cross(right, fwd);
  if (!cam.ortho && !(cam.fov_deg > 0 && cam.fov_deg < 180))
    throw UsageError("field of view must be in (0, 180) degrees");
  const double aspect = double(width) / double(height);
  // Height of the image plane at distance 1 (perspective) or in world units (orthographic).
  double plane_h = 2.0 * std::tan(0.5 * cam.fov_deg * kPi / 180.0);
  if (cam.ortho) plane_h = cam.ortho_height > 0 ? cam.ortho_height : plane_h * dist;
  const double plane_w = plane_h * aspect;
  const vec3d du = right * (plane_w / width);
  const vec3d dv = up * (-plane_h / height);
  CameraView v;
  v.forward = vec3f(fwd);
  v.du = vec3f(du);
  v.dv = vec3f(dv);
  v.ortho = cam.ortho ? 1u : 0u;
  v.origin = vec3f(cam.position);
  const vec3d half = right * (-0.5 * plane_w) + up * (0.5 * plane_h);
  // Orthographic rays start on a plane through the camera position (the camera is placed in
  // front of the data), perspective rays at the eye.
  v.corner = cam.ortho ? vec3f(cam.position + half) : vec3f(fwd + half);
  return v;
}

}  // namespace vs
