// The host side of the AMR renderer: the BVH template built once over all ABRs, per-frame ABR
// classification and refit, and the CPU/CUDA launch of the one integrator (integrator.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "volstream/accel/bvh.h"
#include "volstream/amr/model.h"
#include "volstream/amr/source.h"
#include "volstream/io/image.h"
#include "volstream/render/camera.h"
#include "volstream/render/integrator.h"
#include "volstream/render/transfer_function.h"

namespace vs {

enum class Device { cpu, cuda };
// "auto" (CUDA when a GPU is present), "cpu" or "cuda"; UsageError for cuda without a GPU.
Device resolve_device(const std::string& name);
const char* to_string(Device d);

struct FrameSettings {
  uint32_t width = 512, height = 512;
  IntegratorSettings integrator;  // ref_step <= 0: AmrRenderer::default_reference_step()
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

// ABR i is visible when the transfer function gives some value of its range non-zero opacity,
// or its range contains one of the iso values. Empty ranges (no finite value) are invisible.
std::vector<uint8_t> classify_abrs(const std::vector<Range>& abr_ranges, const TransferTable& tf,
                                   const IntegratorSettings& iso);

class AmrRenderer {
 public:
  // Builds the BVH template over all ABRs (once). Keeps a reference to `topology`.
  AmrRenderer(const AmrTopology& topology, const WorldTransform& transform);

  // Per step or transfer-function change: classify the ABRs from their value ranges and refit
  // the BVH (culled ABRs get empty boxes). skip = false keeps every ABR. Returns visible ABRs.
  uint64_t classify(const std::vector<Range>& abr_ranges, const TransferTable& tf, const IntegratorSettings& iso,
                    bool skip, FrameStats* stats = nullptr);

  // Renders with the current classification. color_values/color_tf may be null.
  Image render(Device device, const float* values, const TransferTable& tf, const float* color_values,
               const TransferTable* color_tf, const Camera& camera, const FrameSettings& settings,
               FrameStats* stats = nullptr) const;

  // The kernel view with host pointers (output pointers left null).
  RenderView host_view(const float* values, const TransferTable& tf, const float* color_values,
                       const TransferTable* color_tf, const Camera& camera, const FrameSettings& settings) const;

  Box3<double> world_bounds() const;
  // The world length over which table alphas apply unchanged: 1/256 of the domain's largest
  // extent, so an image looks the same at any resolution (cell count) of the same field.
  double default_reference_step() const;
  const Bvh& template_bvh() const { return template_; }
  const std::vector<BvhNode>& refit_nodes() const { return nodes_; }
  const AmrTopology& topology() const { return topology_; }

 private:
  const AmrTopology& topology_;
  WorldTransform transform_;
  Bvh template_;                 // all ABRs, never changes
  std::vector<BvhNode> nodes_;   // same topology, boxes refit to the visible ABRs
  std::vector<box3f> abr_boxes_;
};

// Runs render_pixel for every pixel of `view` on all CPU cores (view.rgba must be set).
void render_cpu(const RenderView& view);

}  // namespace vs
