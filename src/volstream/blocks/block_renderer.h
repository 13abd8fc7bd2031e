// Host side of the block raycaster: builds the kd-tree of blocks once per topology, the vertex
// values once per set of field values (set_fields), and runs render_block_pixel over all pixels
// on the CPU or the GPU.
#pragma once
#include <cstdint>

#include "volstream/amr/model.h"
#include "volstream/amr/source.h"
#include "volstream/blocks/blackbody.h"
#include "volstream/blocks/block_integrator.h"
#include "volstream/blocks/kd_blocks.h"
#include "volstream/blocks/vertex_field.h"
#include "volstream/io/image.h"
#include "volstream/render/renderer.h"

namespace vs {

struct BlockFrame {
  uint32_t width = 512, height = 512;
  BlockSettings settings;  // ref_step <= 0: 1/256 of the domain's largest extent (as the ABR renderer)
  // Blackbody optics: rho_max normalises the density; emission and absorption per reference step.
  float rho_max = 1.f, emission = 1.f, absorption = 1.f;
  float emission_power = 1.f;  // BlackbodyView::emission_power
  float log_decades = 0.f;  // > 0: density normalised on a log scale (BlackbodyView::log_decades)
};

struct BlockStats {
  double build_seconds = 0;   // the kd-tree (once per renderer)
  double upload_seconds = 0;  // CUDA only: copies to and from the device
  double render_seconds = 0;  // the integrator (kernel time on CUDA)
  uint64_t samples = 0;
};

class BlockRenderer {
 public:
  BlockRenderer(const AmrTopology& topology, const WorldTransform& transform);  // builds the kd-tree

  // The fields that render() draws, in device order; the caller keeps them alive while rendering.
  // values: the primary field (density for blackbody); temperature: blackbody only (else null).
  // With vertex_values (needed by trilinear reconstruction) their vertex fields are computed
  // here, once, and every render reuses them: call again only when the values change.
  void set_fields(const float* values, const float* temperature = nullptr, bool vertex_values = true);
  double vertex_seconds() const { return vertex_seconds_; }  // of the last set_fields

  // tf: used by the TF optics (may be null for blackbody).
  Image render(const TfView* tf, const Camera& camera, const BlockFrame& frame, Device device = Device::cpu,
               BlockStats* stats = nullptr) const;
  // The kernel view with host pointers to everything (outputs left null).
  BlockRenderView host_view(const TfView* tf, const Camera& camera, const BlockFrame& frame) const;
  const KdBlocks& kd() const { return kd_; }
  Box3<double> world_bounds() const;
  double build_seconds() const { return build_seconds_; }

 private:
  const AmrTopology& topology_;
  WorldTransform transform_;
  KdBlocks kd_;
  BlackbodyTable bb_;
  double build_seconds_ = 0;
  const float* values_ = nullptr;
  const float* temperature_ = nullptr;
  VertexField vertex_values_, vertex_temperature_;  // empty unless set_fields made them
  double vertex_seconds_ = 0;
};

}  // namespace vs
