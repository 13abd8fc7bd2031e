// The frame recipe every caller drives (CLI render/play/bench, Python, viewer, MPI ranks): load a
// dataset once, then per frame say what to show (FrameRequest: camera, transfer function, iso
// values, optics, integrator, step) and get a premultiplied float image and per-stage times.
// Anything may change from one frame to the next; only what changed is redone:
//   read     the step's fields from disk (cached per (field, step))
//   upload   to the device (CUDA; once per loaded field)
//   ranges   per-ABR value ranges (once per loaded field)
//   refit    classify the ABRs for the transfer function and iso values and refit the BVH
//            (when ranges, transfer function, iso values or skipping changed)
//   render   the integrator over all pixels
// The streaming pipeline (stream/render_stages.h) hands values it read and uploaded itself to
// use_values() and runs the stages one by one.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "volstream/amr/ranges.h"
#include "volstream/backend/device.h"
#include "volstream/core/image.h"
#include "volstream/io/dataset.h"
#include "volstream/render/camera.h"
#include "volstream/render/integrators/abr_renderer.h"
#include "volstream/render/integrators/block_renderer.h"
#include "volstream/render/optics/optics.h"

namespace vs {

enum class IntegratorKind {
  abr,     // paper 000: ABRs, tent basis, empty-space skipping, equal jittered steps
  blocks,  // paper 004: kd-tree blocks, nearest/trilinear, fixed steps with an exact last one
};

// Everything one frame shows.
struct FrameRequest {
  int step = 0;
  int field = 0;
  // Isosurface colour field (TF optics, through color_tf) or temperature (blackbody); -1: none.
  int second_field = -1;
  uint32_t width = 512, height = 512;
  Camera camera;
  TransferFunctionSpec tf;
  TransferFunctionSpec color_tf;
  IntegratorSettings integrator;  // ref_step <= 0: 1/256 of the domain
  IntegratorKind kind = IntegratorKind::abr;
  Reconstruction reconstruction = Reconstruction::trilinear;  // blocks
  OpticsKind optics = OpticsKind::tf;
  BlackbodyParams blackbody;
  bool skip = true;                         // abr: empty-space skipping
  RangeMode range_mode = RangeMode::tight;  // abr on the CPU: tight or per-brick ABR ranges
  bool stored_ranges = false;               // abr: the dataset's stored ranges instead
  // Meshes: the encoding that samples (io/dataset.h): the stored one; compact also for a dataset
  // stored in the reference encoding (built at load, CPU); reference only for such a dataset.
  MeshEncoding mesh_encoding = MeshEncoding::stored;
};

struct FrameTimes {
  double read = 0, upload = 0, ranges = 0, classify = 0, refit = 0, render = 0;
  double total() const { return read + upload + ranges + classify + refit + render; }
};

struct FrameReport {
  Device device = Device::cpu;
  FrameTimes seconds;            // this frame's stages (0 for those that were cached)
  uint64_t visible_regions = 0;  // abr: visible ABRs; blocks: every block
  uint64_t region_count = 0;
  uint64_t samples = 0;
  double vertex_seconds = 0;  // blocks: vertex values for trilinear (part of `ranges`)
};

class FrameRenderer {
 public:
  FrameRenderer(const Dataset& dataset, Device device);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // One frame, every stage that the request needs redone: premultiplied linear RGBA floats.
  Image render(const FrameRequest& request, FrameReport* report = nullptr);
  // The same frame as 8-bit sRGB RGB over `background` (sRGB-encoded), rows top to bottom: what
  // PNG frames, video and an image stream take.
  std::vector<uint8_t> render_srgb8(const FrameRequest& request, const vec3f& background,
                                    FrameReport* report = nullptr);

  // The stages one by one, for the streaming pipeline: values of the request's field it owns
  // (host memory on the CPU, device memory on CUDA), valid until the next call; then ranges,
  // refit and render for that request.
  void use_values(const float* primary);
  void compute_ranges(const FrameRequest& request, FrameReport* report = nullptr);
  void refit(const FrameRequest& request, bool rebuild, FrameReport* report = nullptr);
  Image render_image(const FrameRequest& request, FrameReport* report = nullptr);

  // Values of `field` at `step` at world points through the ABRs (amr/probe.h; on the GPU on
  // CUDA, through the same device scene as the frames), NaN outside the data.
  std::vector<float> probe(int field, int step, const std::vector<vec3d>& world_points,
                           MeshEncoding mesh_encoding = MeshEncoding::stored);

  Device device() const { return device_; }
  const Dataset& dataset() const { return dataset_; }
  Box3<double> world_bounds() const;
  Camera default_camera(uint32_t width, uint32_t height) const;
  uint64_t visible_regions() const { return visible_; }

 private:
  struct Impl;
  const Dataset& dataset_;
  Device device_;
  std::unique_ptr<Impl> impl_;
  uint64_t visible_ = 0;
};

// resolve_device, except that "auto" is the CPU where `encoding` builds the compact mesh at load
// from a reference dataset: that one has no CUDA path (a stored compact mesh has).
Device resolve_device(const std::string& name, const Dataset& dataset, MeshEncoding encoding);

// The reference for probe(): the tent-basis sum over every cell, no bricks or ABRs (double
// precision; amr/sampler.h's sample_brute_force).
std::vector<double> probe_brute_force(const Dataset& dataset, int field, int step,
                                      const std::vector<vec3d>& world_points);

}  // namespace vs
