// Without the CUDA backend: the GPU block integrator is a clear error (cuda_available() is false).
#ifndef VOLSTREAM_HAVE_CUDA
#include <stdexcept>

#include "volstream/cuda/block_backend.h"

namespace vs::cuda {
BlockRenderTimes render_blocks(const FrameView<BlockVolume>&, const AmrTopology&, const KdBlocks&, const VertexField*,
                               const VertexField*) {
  throw std::runtime_error("this volstream was built without CUDA");
}
}  // namespace vs::cuda
#endif
