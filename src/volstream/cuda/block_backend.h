// The block integrator (render/integrators/block_renderer.h) on the GPU. Kept apart from
// backend.h: it needs only the kernel view. Links without CUDA too (block_backend_stub.cpp: throws).
#pragma once
#include <cstdint>

#include "volstream/amr/kd_blocks.h"
#include "volstream/amr/model.h"

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

// Renders one frame of `host_view` (host pointers into `topology`, `kd` and vertex fields of
// `vertex_count` entries): deep copies every array it points to, runs the integrator one thread
// per pixel, and copies the image into host_view.rgba (and the sample counts into
// host_view.sample_counts when set). Nothing stays on the device between calls.
BlockRenderTimes render_blocks(const FrameView<BlockVolume>& host_view, const AmrTopology& topology, const KdBlocks& kd,
                               uint64_t vertex_count);

}  // namespace vs::cuda
