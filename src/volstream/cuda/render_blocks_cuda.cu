// A one-off frame of the block integrator on the GPU (block_backend.h), through a DeviceScene.
#include <chrono>

#include "volstream/core/stopwatch.h"
#include "volstream/cuda/backend.h"
#include "volstream/cuda/block_backend.h"
#include "volstream/render/integrators/integrator.h"
#include "volstream/volume/amr_volume.h"
#include "volstream/volume/block_volume.h"

namespace vs::cuda {

BlockRenderTimes render_blocks(const FrameView<BlockVolume>& h, const AmrTopology& topology, const KdBlocks& kd,
                               const VertexField* primary_vertices, const VertexField* second_vertices) {
  const Stopwatch watch;
  DeviceScene scene(topology);
  scene.set_blocks(kd);
  scene.set_vertex_fields(primary_vertices, second_vertices);
  const bool second = h.volume.fields[1] != nullptr;
  DeviceValueBuffers values(second ? 2 : 1, topology.cell_count);
  values.upload(0, h.volume.fields[0], topology.cell_count);
  if (second) values.upload(1, h.volume.fields[1], topology.cell_count);
  BlockRenderTimes times;
  times.upload_seconds = watch.seconds();
  const RenderTimes t = scene.render(h, values.data(0), second ? values.data(1) : nullptr);
  times.upload_seconds += t.upload_seconds;
  times.kernel_seconds = t.kernel_seconds;
  return times;
}

}  // namespace vs::cuda
