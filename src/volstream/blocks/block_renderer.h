// Host side of the block raycaster: builds the kd-tree of blocks once per topology and runs
// render_block_pixel over all pixels on the CPU.
#pragma once
#include <cstdint>

#include "volstream/amr/model.h"
#include "volstream/amr/source.h"
#include "volstream/blocks/blackbody.h"
#include "volstream/blocks/block_integrator.h"
#include "volstream/blocks/kd_blocks.h"
#include "volstream/blocks/vertex_field.h"
#include "volstream/io/image.h"

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
  double build_seconds = 0, render_seconds = 0;
  double vertex_seconds = 0;  // trilinear: vertex values of the field(s), per frame (not in render_seconds)
  uint64_t samples = 0;
};

class BlockRenderer {
 public:
  BlockRenderer(const AmrTopology& topology, const WorldTransform& transform);  // builds the kd-tree
  // values: the primary field (density for blackbody); temperature: blackbody only (else null);
  // tf: used by the TF optics (may be null for blackbody).
  Image render(const float* values, const float* temperature, const TfView* tf, const Camera& camera,
               const BlockFrame& frame, BlockStats* stats = nullptr) const;
  // The kernel view with host pointers (vertex fields and outputs left null).
  BlockRenderView host_view(const float* values, const float* temperature, const TfView* tf, const Camera& camera,
                            const BlockFrame& frame) const;
  const KdBlocks& kd() const { return kd_; }
  Box3<double> world_bounds() const;
  double build_seconds() const { return build_seconds_; }

 private:
  const AmrTopology& topology_;
  WorldTransform transform_;
  KdBlocks kd_;
  BlackbodyTable bb_;
  double build_seconds_ = 0;
};

}  // namespace vs
