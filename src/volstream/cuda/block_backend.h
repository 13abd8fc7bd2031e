// The block integrator (render/integrators/block_renderer.h) on the GPU. Kept apart from
// backend.h: it needs only the kernel view. Links without CUDA too (block_backend_stub.cpp: throws).
#pragma once
#include <cstdint>

#include "volstream/amr/kd_blocks.h"
#include "volstream/amr/model.h"
#include "volstream/amr/vertex_field.h"

namespace vs {
template <typename V>
struct FrameView;
struct BlockVolume;
}  // namespace vs

namespace vs::cuda {

struct BlockRenderTimes {
  double upload_seconds = 0;    // allocating and copying every input array to the device
  double kernel_seconds = 0;    // the integrator over all pixels (CUDA events)
  double download_seconds = 0;  // the image and sample counts back
};

// Renders one frame of `host_view` (host pointers into `topology`, `kd` and the vertex fields,
// null when not used) through a DeviceScene made for it, and copies the image into
// host_view.rgba (and the sample counts into host_view.sample_counts when set). Frame loops keep
// a DeviceScene instead (frame/frame_renderer.h).
BlockRenderTimes render_blocks(const FrameView<BlockVolume>& host_view, const AmrTopology& topology, const KdBlocks& kd,
                               const VertexField* primary_vertices, const VertexField* second_vertices);

}  // namespace vs::cuda
