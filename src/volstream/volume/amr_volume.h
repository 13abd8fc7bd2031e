// AMR through active brick regions (paper 000): the regions are the ABRs, found front to back by
// the refit BVH (culled ABRs have empty boxes and are never hit), and fields are reconstructed
// with the tent basis over each ABR's bricks only (amr/sampler.h).
#pragma once
#include <cmath>
#include <cstdint>

#include "volstream/accel/bvh_traverse.h"
#include "volstream/accel/bvh_wide.h"
#include "volstream/amr/model.h"
#include "volstream/amr/sampler.h"
#include "volstream/volume/volume.h"

namespace vs {

struct AmrVolume {
  AmrView amr;                              // topology (amr.values unused: see fields)
  const float* fields[kVolumeFields] = {};  // device order; fields[1] may be null
  const BvhNode* nodes = nullptr;           // refit BVH: visible ABRs only
  uint32_t node_count = 0;
  const Bvh4Node* wide_nodes = nullptr;  // CPU: its 4-wide form (bvh_wide.h); null on the GPU
  uint32_t wide_node_count = 0;
  const BvhNode* all_nodes = nullptr;  // template BVH over all ABRs: point location
  uint32_t all_node_count = 0;
  // The CPU's fast sampler's records (amr/sampler.h, one per brick); null: the reference
  // sampler (the GPU, and tests that compare the two).
  const SampleBrick* sample_bricks = nullptr;
  bool lane_offsets = false;  // their value offsets fit 32-bit lanes (sample_abrs_batch)

  VS_HOST_DEVICE float sample(int field, uint32_t abr, const vec3f& p) const {
    if (sample_bricks) return sample_abr_fast(amr.abrs, amr.abr_bricks, sample_bricks, fields[field], abr, p);
    AmrView v = amr;
    v.values = fields[field];
    return sample_abr(v, abr, p);
  }
#if !defined(__CUDA_ARCH__)
  // The CPU's batches (integrator.h): n <= 8 points org + dir * t[i] of one ABR; the same values
  // as sample() per point, in SIMD lanes (amr/sampler.h).
  void sample_batch(int field, uint32_t abr, const vec3f& org, const vec3f& dir, const float* t, uint32_t n,
                    float* out) const {
    if (!sample_bricks) {
      for (uint32_t i = 0; i < n; ++i) out[i] = sample(field, abr, org + dir * t[i]);
      return;
    }
    const Abr& a = amr.abrs[abr];
    const uint32_t* ids = amr.abr_bricks + a.first_brick;
    if (a.brick_count == 1) return sample_one_brick_batch(sample_bricks[ids[0]], fields[field], org, dir, t, n, out);
    sample_bricks_batch(sample_bricks, ids, a.brick_count, fields[field], org, dir, t, n, out);
  }
  // The same for n <= 8 points of several ABRs, point i in ABR regions[i] (a ray's samples over
  // short intervals, integrator.h).
  void sample_regions_batch(int field, const uint32_t* regions, const vec3f& org, const vec3f& dir, const float* t,
                            uint32_t n, float* out) const {
    bool one_region = true;
    for (uint32_t i = 1; i < n; ++i) one_region &= regions[i] == regions[0];
    if (one_region) return sample_batch(field, regions[0], org, dir, t, n, out);
    if (sample_bricks && lane_offsets)
      return sample_abrs_batch({amr.abrs, amr.abr_bricks, sample_bricks}, fields[field], regions, org, dir, t, n, out);
    for (uint32_t i = 0; i < n; ++i) out[i] = sample(field, regions[i], org + dir * t[i]);
  }
#endif
  VS_HOST_DEVICE int64_t locate(const vec3f& p) const {
    return bvh_locate(
        all_nodes, all_node_count, [&](uint32_t i) { return amr.abrs[i].box; }, p);
  }
  VS_HOST_DEVICE float sample_near(int field, uint32_t abr, const vec3f& p) const {
    if (amr.abrs[abr].box.contains(p)) return sample(field, abr, p);
    const int64_t other = locate(p);
    return other < 0 ? NAN : sample(field, uint32_t(other), p);
  }
  VS_HOST_DEVICE float step_width(uint32_t abr) const { return amr.abrs[abr].finest_width; }

  // ABR segments come K at a time from one traversal (bvh_next_leaves), front to back.
  template <typename Visit>
  VS_HOST_DEVICE void for_each_interval(const vec3f& org, const vec3f& dir, Visit&& visit) const {
    for_each_region_leaf(nodes, node_count, wide_nodes, wide_node_count, org, dir,
                         [&](uint32_t abr, float t0, float t1) {
                           return visit(RayInterval{abr, t0, t1});
                         });
  }
};
static_assert(Volume<AmrVolume>);

}  // namespace vs
