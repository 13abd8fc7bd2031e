// The block raycaster of paper 004 (blocks/block_integrator.h) on the GPU. Kept apart from
// backend.h: it needs only the kernel view. Links without CUDA too (block_backend_stub.cpp: throws).
#pragma once

namespace vs {
struct BlockRenderView;
}  // namespace vs

namespace vs::cuda {

struct BlockRenderTimes {
  double upload_seconds = 0;    // allocating and copying every input array to the device
  double kernel_seconds = 0;    // render_block_pixel over all pixels (CUDA events)
  double download_seconds = 0;  // the image and sample counts back
};

// Renders one frame of `host_view` (host pointers with their counts, see BlockRenderView): deep
// copies every array it points to (kd-tree, blocks, bricks, values, vertex fields, transfer and
// blackbody tables), runs render_block_pixel one thread per pixel, and copies the image into
// host_view.rgba (and the sample counts into host_view.sample_counts when set). Nothing stays
// on the device between calls.
BlockRenderTimes render_blocks(const BlockRenderView& host_view);

}  // namespace vs::cuda
