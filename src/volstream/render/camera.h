// Cameras (perspective and orthographic) in world space, and the per-pixel ray generator that
// kernels use. Rays are generated in world space with unit direction, so the ray parameter t is
// a world distance; the integrator maps origin and direction to grid units with the same t.
#pragma once
#include <cstdint>

#include "volstream/core/math.h"

namespace vs {

struct Camera {
  vec3d position{0, 0, 1};
  vec3d look_at{0, 0, 0};
  vec3d up{0, 1, 0};
  double fov_deg = 35;  // vertical field of view (perspective)
  bool ortho = false;
  double ortho_height = 0;  // world height of the view (orthographic); 0: the height a
                            // perspective camera sees at the look-at distance
};

// A camera looking at the centre of `world_box` from a diagonal (front, right, above), far
// enough that the whole box is in view for the given aspect ratio (width / height).
Camera default_camera(const Box3<double>& world_box, double aspect);

// What the kernel sees: a pinhole (or parallel projection) with the image plane spanned by
// du (one pixel to the right) and dv (one pixel down) from the top-left pixel corner.
struct CameraView {
  vec3f origin;   // eye (perspective) or centre of the image plane (orthographic)
  vec3f corner;   // perspective: direction to the top-left corner; ortho: its world position
  vec3f du, dv;   // per pixel
  vec3f forward;  // view direction (unit)
  uint32_t ortho = 0;

  // Ray through image position (x, y) in pixels (0,0 = top-left corner of the image).
  VS_HOST_DEVICE void ray(float x, float y, vec3f& org, vec3f& dir) const {
    if (ortho) {
      org = corner + du * x + dv * y;
      dir = forward;
    } else {
      org = origin;
      dir = normalize(corner + du * x + dv * y);
    }
  }
};

// Throws UsageError for degenerate cameras (position == look_at, up parallel to the view, bad fov).
CameraView make_camera_view(const Camera& camera, uint32_t width, uint32_t height);

}  // namespace vs
