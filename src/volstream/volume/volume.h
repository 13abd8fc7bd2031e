// The interface integrators sample through (DESIGN.md principle 6): a volume kind hands a ray its
// regions front to back and reconstructs fields inside them; it never has its own integrator,
// optics or compositing. Implementations are plain structs of pointers (host or device) with
// VS_HOST_DEVICE members, used as template arguments: no virtual calls in kernels.
//
// A Volume V provides, in grid units (the ray's parameter t is a world distance, see
// render/integrators/integrator.h):
//   v.for_each_interval(org, dir, visit)  visit(RayInterval) for every visible region the ray
//                                         crosses, front to back, disjoint; visit returns false
//                                         to stop the walk (early ray termination); a volume
//                                         whose sample ignores the region may hand adjacent
//                                         regions over as one interval, named by the region whose
//                                         step width it marches (MeshVolume)
//   v.sample(field, region, p)            field 0 (primary) or 1 (second: colour or temperature)
//                                         at p inside `region`; NaN where the volume has no data
//   v.sample_near(field, region, p)       the same for p near `region`, possibly outside it (the
//                                         volume locates p): gradient stencils cross region faces
//   v.step_width(region)                  the region's finest feature size: adaptive sampling
//                                         steps width / rate
//   v.locate(p)                           the region containing p, or -1
// and optionally, with a type V::Hint, sample(field, region, p, hint) and sample_near(..., hint)
// with the V::Hint (value-initialised for each ray) that the integrator keeps per ray
// (RayState::hint): the volume's note of where the previous sample was found (a mesh's element,
// and a tet's solve), which it may read and update to find the next one faster.
//
// Value ranges per region (for empty-space skipping and classification, render/skipping.h) and
// region boxes (for the refit BVH) are the host side of a volume kind: amr/ranges.h for ABRs.
#pragma once
#include <concepts>
#include <cstdint>

#include "volstream/core/math.h"

namespace vs {

struct RayInterval {
  uint32_t region;
  float t0, t1;  // entry and exit (world distance along the ray)
};

inline constexpr int kVolumeFields = 2;  // primary + one second field

struct IntervalSink {  // the shape of a visit callback, for the concept check only
  bool operator()(const RayInterval&) const { return true; }
};

template <typename V>
concept Volume = requires(const V& v, const vec3f& p, uint32_t region, int field, IntervalSink visit) {
  v.for_each_interval(p, p, visit);
  { v.sample(field, region, p) } -> std::convertible_to<float>;
  { v.sample_near(field, region, p) } -> std::convertible_to<float>;
  { v.step_width(region) } -> std::convertible_to<float>;
  { v.locate(p) } -> std::convertible_to<int64_t>;
};

}  // namespace vs
