// The host side of paper 000's ABR integrator: the volume's regions are the ABRs (AmrVolume), a
// BVH template over all of them is built once, and per frame the ABRs are classified from their
// value ranges and the BVH refit (culled ABRs get empty boxes); then the one integrator
// (integrator.h) runs on the CPU or the GPU.
#pragma once
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "volstream/accel/bvh.h"
#include "volstream/amr/model.h"
#include "volstream/amr/source.h"
#include "volstream/backend/device.h"
#include "volstream/backend/memory.h"
#include "volstream/core/error.h"
#include "volstream/core/image.h"
#include "volstream/core/stopwatch.h"
#include "volstream/render/camera.h"
#include "volstream/render/integrators/integrator.h"
#include "volstream/render/integrators/launch_cpu.h"
#include "volstream/render/optics/optics.h"
#include "volstream/render/skipping.h"
#include "volstream/volume/amr_volume.h"

namespace vs {

struct FrameSettings {
  uint32_t width = 512, height = 512;
  IntegratorSettings integrator;  // ref_step <= 0: default_reference_step()
  bool skip = true;               // empty-space skipping: cull ABRs that cannot contribute
  bool brick_ranges = false;      // CPU: cull by per-brick ranges (cheaper, looser; amr/ranges.h)
};

struct FrameStats {
  Device device = Device::cpu;
  uint64_t visible_abrs = 0;
  double classify_seconds = 0, refit_seconds = 0;
  double upload_seconds = 0;  // CUDA only: copies to the device
  double render_seconds = 0;  // the integrator (kernel time on CUDA)
  uint64_t samples = 0;       // reconstructions of the field (incl. gradients and root refinement)
};

// The world length over which table alphas apply unchanged by default: 1/256 of the domain's
// largest extent, so an image looks the same at any resolution (cell count) of the same field.
double default_reference_step(const Box3<double>& world_bounds);

// The kernel's grid map of a world transform.
GridMap make_grid_map(const WorldTransform& transform);

// The frame's settings with the defaults filled in (ref_step) and checked (rate).
IntegratorSettings resolve_settings(IntegratorSettings s, const Box3<double>& world_bounds);

// Fields a frame samples, in device order: the primary one and an optional second one (the
// isosurfaces' colour field, or the temperature of the blackbody optics).
struct FrameFields {
  const float* primary = nullptr;
  const float* second = nullptr;
};

// The parts of a frame view every volume kind fills alike: optics, colour isosurfaces (when a
// second field is given), camera, grid map and resolved settings.
template <typename V>
void fill_frame(FrameView<V>& v, const OpticsView& optics, const TfView* color_tf, bool has_second,
                const Camera& camera, const FrameSettings& settings, const WorldTransform& transform,
                const Box3<double>& world_bounds) {
  if (optics.needs_second_field() && !has_second) throw UsageError("blackbody optics needs a temperature field");
  v.optics = optics;
  if (color_tf && has_second) {
    v.color_isosurfaces = 1;
    v.color_tf = *color_tf;
  }
  v.camera = make_camera_view(camera, settings.width, settings.height);
  v.grid = make_grid_map(transform);
  v.settings = resolve_settings(settings.integrator, world_bounds);
  v.width = settings.width;
  v.height = settings.height;
}

// Renders a view on the CPU into a new image; adds the integrator's time and samples to stats.
template <typename V>
Image render_view_cpu(FrameView<V> view, FrameStats* stats) {
  Image img(view.width, view.height);
  view.rgba = img.rgba.data();
  view.sample_counts = nullptr;  // summed by the launch
  Stopwatch watch;
  const uint64_t samples = render_frame_cpu(view);
  if (stats) {
    stats->device = Device::cpu;
    stats->render_seconds = watch.seconds();
    stats->samples = samples;
  }
  return img;
}

class AmrRenderer {
 public:
  // Builds the BVH template over all ABRs (once). Keeps a reference to `topology`.
  AmrRenderer(const AmrTopology& topology, const WorldTransform& transform);
  // The same for a rank's share of a dataset (mpi/): defaults such as the reference step follow
  // the whole dataset's world bounds, not the share's.
  AmrRenderer(const AmrTopology& topology, const WorldTransform& transform, const Box3<double>& world_bounds);

  // Per step or transfer-function change: classify the ABRs from their value ranges and refit
  // the BVH (culled ABRs get empty boxes). skip = false keeps every ABR. Returns visible ABRs.
  uint64_t classify(const std::vector<Range>& abr_ranges, const TransferTable& tf, const IntegratorSettings& iso,
                    bool skip, FrameStats* stats = nullptr);

  // Refits the BVH to the ABRs with keep[i] != 0 (empty: all). Returns visible ABRs.
  uint64_t refit(const std::vector<uint8_t>& keep, FrameStats* stats = nullptr);

  // The kernel view with host pointers (outputs left null). color_tf: colour the isosurfaces by
  // fields.second (else null).
  FrameView<AmrVolume> view(const FrameFields& fields, const OpticsView& optics, const TfView* color_tf,
                            const Camera& camera, const FrameSettings& settings) const;
  // Renders a view made by view() on the device.
  Image render(Device device, const FrameView<AmrVolume>& host_view, FrameStats* stats = nullptr) const;

  // The transfer-function optics with an optional colour field for the isosurfaces.
  Image render(Device device, const float* values, const TransferTable& tf, const float* color_values,
               const TransferTable* color_tf, const Camera& camera, const FrameSettings& settings,
               FrameStats* stats = nullptr) const;

  Box3<double> world_bounds() const { return world_bounds_; }
  double default_reference_step() const { return vs::default_reference_step(world_bounds()); }
  const Bvh& template_bvh() const { return skipping_.template_bvh(); }
  const std::vector<BvhNode>& refit_nodes() const { return skipping_.refit_nodes(); }
  const AmrTopology& topology() const { return topology_; }

 private:
  const AmrTopology& topology_;
  WorldTransform transform_;
  Box3<double> world_bounds_;
  RegionBvh skipping_;  // over the ABR boxes
  // The CPU's fast sampler's records (amr/sampler.h), built once with the renderer.
  std::vector<SampleBrick> sample_bricks_;
  bool lane_offsets_;  // sample_bricks_' value offsets fit 32-bit lanes
  CountedBytes sample_bricks_bytes_;
};

// The world box of the leaf cells.
Box3<double> world_bounds(const AmrTopology& topology, const WorldTransform& transform);

}  // namespace vs
