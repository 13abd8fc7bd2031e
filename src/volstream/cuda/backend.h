// What the host code may ask of the CUDA backend. Everything here also links without CUDA:
// cuda_available() is then false and the other calls throw.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "volstream/accel/bvh.h"
#include "volstream/amr/model.h"

namespace vs {
template <typename V>
struct FrameView;
struct AmrVolume;
struct BlockVolume;
struct KdBlocks;
struct VertexField;
struct IntegratorSettings;
class TransferTable;
}  // namespace vs

namespace vs::cuda {

bool cuda_available();      // compiled with CUDA and a device is present
std::string device_name();  // e.g. "NVIDIA H100 80GB HBM3"; empty without a device

// The same computation as vs::probe_points, on the GPU.
std::vector<float> probe_points(const AmrTopology& topology, const Bvh& bvh, const float* values,
                                const std::vector<vec3f>& grid_points);

struct RenderTimes {
  double upload_seconds = 0, kernel_seconds = 0;
};

// GPU-resident state for rendering frames of one topology (paper 000, section 5), the one place
// where device memory for a dataset lives: the ABR integrator, the block integrator and point
// probes all read the same bricks; every buffer is counted in the memory ledger. The topology
// and the BVH template are uploaded once; per frame only the values change (DeviceValueBuffers),
// and the ranges, classification and refit run on the GPU, so nothing of the size of the ABR
// list crosses the bus. Each call returns when its work is done, but the work runs on the
// scene's own non-blocking stream: an upload issued meanwhile by another thread on its own
// stream overlaps it (section 5.7). Scratch buffers only grow, so a steady frame loop allocates
// and frees nothing (cudaFree would wait for that upload).
class DeviceScene {
 public:
  explicit DeviceScene(const AmrTopology& topology);  // uploads the topology; keeps no reference
  ~DeviceScene();
  DeviceScene(const DeviceScene&) = delete;
  DeviceScene& operator=(const DeviceScene&) = delete;

  // The BVH template over all ABRs (from the renderer; again after every rebuild). The refit
  // nodes start as a copy of it.
  void set_bvh(const std::vector<BvhNode>& template_nodes);
  // The "ranges" stage: per-ABR value ranges of `device_values` (amr/ranges.h), kept on the GPU.
  void compute_ranges(const float* device_values);
  std::vector<Range> download_ranges() const;
  // The "refit" stage: classify every ABR from the last computed ranges (render/classify.h)
  // and refit the BVH group by group (accel/refit.h); skip = false keeps every ABR. Returns
  // the number of visible ABRs.
  uint64_t classify_and_refit(const TransferTable& tf, const IntegratorSettings& iso, bool skip);
  // For a host-side classification instead: the refit nodes as the host computed them.
  void set_refit_nodes(const std::vector<BvhNode>& nodes);
  std::vector<BvhNode> download_refit_nodes() const;

  // Renders `host_view` (camera, settings and optics tables from the host; its topology, BVH
  // and field pointers are replaced by the scene's and the given device arrays) and copies the
  // image (and the sample counts when host_view.sample_counts is set) back to host_view.rgba.
  RenderTimes render(const FrameView<AmrVolume>& host_view, const float* device_values, const float* device_second);

  // The block integrator's kd-tree and blocks (once per topology) and vertex values (once per
  // set of field values; null: none), then frames as render() above.
  void set_blocks(const KdBlocks& kd);
  void set_vertex_fields(const VertexField* primary, const VertexField* second);
  RenderTimes render(const FrameView<BlockVolume>& host_view, const float* device_values, const float* device_second);

  // Field values at points (grid units) through the BVH template (amr/probe.h): NaN outside.
  std::vector<float> probe(const float* device_values, const std::vector<vec3f>& grid_points);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Field values in GPU memory, filled from host memory on a stream of their own.
class DeviceValueBuffers {
 public:
  DeviceValueBuffers(int count, uint64_t floats_each);  // allocates all of them up front
  ~DeviceValueBuffers();
  DeviceValueBuffers(const DeviceValueBuffers&) = delete;
  DeviceValueBuffers& operator=(const DeviceValueBuffers&) = delete;
  const float* data(int buffer) const;
  // Copies `floats` values into `buffer`; returns when done. From page-locked memory the copy is
  // DMA that overlaps kernels running on other streams; from pageable memory the driver stages it.
  void upload(int buffer, const float* host, uint64_t floats);
  uint64_t bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One frame from host data: uploads the topology, the BVHs and the values (through a
// DeviceScene), renders `host_view` as classified and refit on the host, copies the image back.
RenderTimes render(const AmrTopology& topology, const FrameView<AmrVolume>& host_view);

}  // namespace vs::cuda
