// The host side of paper 004's block integrator: the volume's regions are the same-level blocks
// of a kd-tree over the bricks (BlockVolume), built once per topology; vertex values for
// trilinear reconstruction are built once per set of field values (set_fields). The march is
// paper 004's (fixed steps of the block's cell width / rate, the last one exact); everything
// else (rays, optics, isosurfaces, compositing) is the one integrator (integrator.h).
#pragma once
#include <cstdint>

#include "volstream/amr/kd_blocks.h"
#include "volstream/amr/model.h"
#include "volstream/amr/source.h"
#include "volstream/amr/vertex_field.h"
#include "volstream/backend/memory.h"
#include "volstream/render/integrators/abr_renderer.h"
#include "volstream/render/optics/blackbody.h"
#include "volstream/volume/block_volume.h"

namespace vs {

using Optics = OpticsKind;

struct BlockSettings {
  float rate = 2.f;      // samples per cell width of each block's level
  float ref_step = 1.f;  // world length over which table alphas / coefficients apply unchanged
  Reconstruction reconstruction = Reconstruction::trilinear;
  Optics optics = Optics::tf;
};

struct BlockFrame {
  uint32_t width = 512, height = 512;
  BlockSettings settings;  // ref_step <= 0: 1/256 of the domain's largest extent (as the ABR renderer)
  BlackbodyParams blackbody;
  // Isosurfaces, shading and rays per pixel (the other integrator settings come from `settings`).
  IntegratorSettings integrator;
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
  // values: the primary field (density for blackbody); second: the temperature for blackbody or
  // the isosurfaces' colour field (else null). With vertex_values (needed by trilinear
  // reconstruction) their vertex fields are computed here, once, and every render reuses them:
  // call again only when the values change.
  void set_fields(const float* values, const float* second = nullptr, bool vertex_values = true);
  double vertex_seconds() const { return vertex_seconds_; }  // of the last set_fields
  const VertexField* vertex_field(int field) const;          // 0 or 1; null when not built

  // tf: the transfer function (may be null for blackbody); color_tf: colours isosurfaces by the
  // second field.
  Image render(const TfView* tf, const Camera& camera, const BlockFrame& frame, Device device = Device::cpu,
               BlockStats* stats = nullptr, const TfView* color_tf = nullptr) const;
  // The kernel view with host pointers to everything (outputs left null).
  FrameView<BlockVolume> view(const TfView* tf, const Camera& camera, const BlockFrame& frame,
                              const TfView* color_tf = nullptr) const;
  const KdBlocks& kd() const { return kd_; }
  Box3<double> world_bounds() const;
  double build_seconds() const { return build_seconds_; }

 private:
  const AmrTopology& topology_;
  WorldTransform transform_;
  KdBlocks kd_;
  double build_seconds_ = 0;
  const float* values_ = nullptr;
  const float* second_ = nullptr;
  VertexField vertex_values_, vertex_second_;  // empty unless set_fields made them
  double vertex_seconds_ = 0;
  CountedBytes kd_bytes_, vertex_bytes_;  // host memory
};

}  // namespace vs
