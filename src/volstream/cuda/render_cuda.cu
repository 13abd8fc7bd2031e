// The GPU side of rendering (backend.h): a DeviceScene holding the topology and BVHs, and the
// per-frame ranges, classification, refit and render kernels. The kernels call the same
// host-device functions as the CPU path (amr/ranges.h, render/classify.h, accel/refit.h,
// render/integrators/integrator.h); only memory handling lives here.
#include <chrono>

#include "volstream/accel/refit.h"
#include "volstream/amr/probe.h"
#include "volstream/amr/ranges.h"
#include "volstream/core/stopwatch.h"
#include "volstream/cuda/backend.h"
#include "volstream/cuda/launch.cuh"
#include "volstream/cuda/render_frame.cuh"
#include "volstream/render/classify.h"
#include "volstream/render/optics/transfer_function.h"
#include "volstream/volume/amr_volume.h"
#include "volstream/volume/block_volume.h"

namespace vs::cuda {
namespace {

constexpr unsigned kFullWarp = 0xffffffffu;

// A non-blocking stream: it never waits for the legacy default stream, nor it for it.
struct Stream {
  cudaStream_t s = nullptr;
  Stream() { VS_CUDA_CHECK(cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking)); }
  ~Stream() { cudaStreamDestroy(s); }
  Stream(const Stream&) = delete;
  Stream& operator=(const Stream&) = delete;
  void sync() const { VS_CUDA_CHECK(cudaStreamSynchronize(s)); }
};

// Pass 2 of amr/ranges.h: one warp per ABR; the lanes stride together over each brick's
// macrocells near the ABR and combine their partial ranges with shuffles.
__global__ void abr_ranges_kernel(RangeView v, Range* out) {
  // 64-bit thread index: 32 threads per ABR overflow 32 bits from 2^27 ABRs on.
  const uint64_t warp = (uint64_t(blockIdx.x) * blockDim.x + threadIdx.x) / 32u;
  const uint32_t lane = threadIdx.x % 32u;
  if (warp >= v.amr.abr_count) return;  // uniform per warp: blockDim is a multiple of 32
  Range r = abr_lane_range(v, uint32_t(warp), lane, 32u);
  for (int offset = 16; offset > 0; offset /= 2) {
    r.lo = fminf(r.lo, __shfl_xor_sync(kFullWarp, r.lo, offset));
    r.hi = fmaxf(r.hi, __shfl_xor_sync(kFullWarp, r.hi, offset));
  }
  if (lane == 0) out[warp] = widen_for_rounding(r);
}

// Adds the number of threads of the calling warp with `flag` set to *count: one atomic per warp.
__device__ void count_per_warp(bool flag, unsigned long long* count) {
  const unsigned active = __activemask();
  const unsigned votes = __ballot_sync(active, flag);
  if ((threadIdx.x % 32u) == unsigned(__ffs(active) - 1)) atomicAdd(count, (unsigned long long)__popc(votes));
}

}  // namespace

struct DeviceScene::Impl {
  uint32_t brick_count = 0, abr_count = 0;
  DeviceBuffer<Brick> bricks{"bricks"};
  DeviceBuffer<Abr> abrs{"ABRs"};
  DeviceBuffer<uint32_t> abr_bricks{"ABR brick lists"};
  DeviceBuffer<BvhNode> template_nodes{"BVH"}, refit_nodes{"BVH (refit)"};
  DeviceBuffer<uint32_t> schedule{"BVH (refit)"};     // RefitSchedule::nodes
  std::vector<uint32_t> group_begin;                  // RefitSchedule::group_begin (host: launch bounds)
  DeviceBuffer<uint64_t> macro_offset{"ABR ranges"};  // macrocell_offsets(bricks)
  DeviceBuffer<Range> macro{"ABR ranges"}, ranges{"ABR ranges"};
  DeviceBuffer<uint8_t> keep{"ABR ranges"};
  DeviceBuffer<uint32_t> opaque_prefix{"transfer tables"};
  DeviceBuffer<unsigned long long> counter{"ABR ranges"};
  DeviceOpticsTables tables;  // the frame's; classification reads tables.tf too
  DeviceBuffer<KdNode> kd_nodes{"kd-tree blocks"};
  DeviceBuffer<Block> blocks{"kd-tree blocks"};
  DeviceBuffer<uint64_t> vertex_offsets{"vertex values"};
  DeviceBuffer<float> vertex_fields[kVolumeFields] = {DeviceBuffer<float>{"vertex values"},
                                                      DeviceBuffer<float>{"vertex values"}};
  DeviceBuffer<float> rgba{"image"};
  DeviceBuffer<uint32_t> counts{"image"};
  Stream stream;

  AmrView view(const float* values) const {
    return {bricks.data(), abrs.data(), abr_bricks.data(), values, brick_count, abr_count};
  }

  // The tables of the host view's optics on the device (transfer function, blackbody colours,
  // isosurface colours) and the image buffers; returns the device view with those pointers.
  template <typename V>
  FrameView<V> device_view(const FrameView<V>& h) {
    const size_t pixels = size_t(h.width) * h.height;
    FrameView<V> d = h;
    tables.upload(h, d, stream.s);
    rgba.ensure(4 * pixels);
    if (h.sample_counts) counts.ensure(pixels);
    d.rgba = rgba.data();
    d.sample_counts = h.sample_counts ? counts.data() : nullptr;
    return d;
  }

  // Runs the integrator over `d` and copies the image (and sample counts) to the host view's.
  template <typename V>
  RenderTimes render(const FrameView<V>& h, const FrameView<V>& d, double upload_seconds) {
    RenderTimes times;
    times.upload_seconds = upload_seconds;
    const size_t pixels = size_t(h.width) * h.height;
    times.kernel_seconds = render_frame(d, stream.s);
    VS_CUDA_CHECK(cudaMemcpyAsync(h.rgba, d.rgba, 4 * pixels * sizeof(float), cudaMemcpyDeviceToHost, stream.s));
    if (h.sample_counts)
      VS_CUDA_CHECK(cudaMemcpyAsync(h.sample_counts, d.sample_counts, pixels * sizeof(uint32_t), cudaMemcpyDeviceToHost,
                                    stream.s));
    sync();
    return times;
  }

  void sync() {
    stream.sync();
    collect_launch_times();
  }
};

DeviceScene::DeviceScene(const AmrTopology& topology) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.brick_count = uint32_t(topology.bricks.size());
  m.abr_count = uint32_t(topology.abrs.size());
  m.bricks.upload(topology.bricks);
  m.abrs.upload(topology.abrs);
  m.abr_bricks.upload(topology.abr_bricks);
  const std::vector<uint64_t> offsets = macrocell_offsets(topology.bricks);
  m.macro_offset.upload(offsets);
  m.macro.resize(offsets.back());
  m.ranges.resize(m.abr_count);
  m.keep.resize(m.abr_count);
  m.counter.resize(1);
  ensure_integrator_stack();
}

DeviceScene::~DeviceScene() = default;

void DeviceScene::set_bvh(const std::vector<BvhNode>& template_nodes) {
  Impl& m = *impl_;
  const RefitSchedule schedule = refit_schedule(template_nodes);
  m.template_nodes.upload(template_nodes);
  m.refit_nodes.upload(template_nodes);
  m.schedule.upload(schedule.nodes);
  m.group_begin = schedule.group_begin;
}

void DeviceScene::compute_ranges(const float* device_values) {
  Impl& m = *impl_;
  const RangeView view{m.view(device_values), m.macro_offset.data(), m.macro.data()};
  parallel_for(
      "macrocells", int64_t(m.macro.size()), [=] __device__(int64_t i) { compute_macrocell(view, uint64_t(i)); },
      m.stream.s);
  constexpr unsigned kBlock = 128;  // 4 warps, 4 ABRs per block
  const uint64_t threads = uint64_t(m.abr_count) * 32u;
  if (threads > 0) {
    TimedLaunch timed("abr_ranges", m.stream.s);
    abr_ranges_kernel<<<unsigned((threads + kBlock - 1) / kBlock), kBlock, 0, m.stream.s>>>(view, m.ranges.data());
    check(cudaGetLastError(), "abr_ranges_kernel", __FILE__, __LINE__);
    timed.stop();
  }
  m.sync();
}

std::vector<Range> DeviceScene::download_ranges() const { return impl_->ranges.download(); }

uint64_t DeviceScene::classify_and_refit(const TransferTable& table, const IntegratorSettings& iso, bool skip) {
  Impl& m = *impl_;
  if (m.group_begin.empty() && m.abr_count > 0) throw std::logic_error("DeviceScene: set_bvh() before refit");
  uint8_t* keep = nullptr;
  uint64_t visible = m.abr_count;
  if (skip) {
    m.tables.tf.upload_async(table.entries().data(), table.entries().size(), m.stream.s);
    m.opaque_prefix.upload_async(table.opaque_prefix().data(), table.opaque_prefix().size(), m.stream.s);
    OpacityIndex opacity = table.opacity_index();
    opacity.tf.table = m.tables.tf.data();
    opacity.opaque_prefix = m.opaque_prefix.data();
    VS_CUDA_CHECK(cudaMemsetAsync(m.counter.data(), 0, sizeof(unsigned long long), m.stream.s));
    keep = m.keep.data();
    const Range* ranges = m.ranges.data();
    unsigned long long* counter = m.counter.data();
    const IntegratorSettings settings = iso;
    parallel_for(
        "classify", int64_t(m.abr_count),
        [=] __device__(int64_t i) {
          const bool v = abr_visible(ranges[i], opacity, settings);
          keep[i] = v ? 1 : 0;
          count_per_warp(v, counter);
        },
        m.stream.s);
  }
  BvhNode* nodes = m.refit_nodes.data();
  const uint32_t* order = m.schedule.data();
  const Abr* abrs = m.abrs.data();
  const uint8_t* kept = keep;
  for (size_t g = 0; g + 1 < m.group_begin.size(); ++g) {
    const uint32_t begin = m.group_begin[g];
    parallel_for(
        "refit", int64_t(m.group_begin[g + 1] - begin),
        [=] __device__(int64_t k) {
          refit_node(
              nodes, order[begin + k], [=](uint32_t i) { return abrs[i].box; }, kept);
        },
        m.stream.s);
  }
  unsigned long long count = 0;
  if (skip) VS_CUDA_CHECK(cudaMemcpyAsync(&count, m.counter.data(), sizeof(count), cudaMemcpyDeviceToHost, m.stream.s));
  m.sync();
  if (skip) visible = count;  // read after the stream is done, not when cudaMemcpyAsync returns
  return visible;
}

void DeviceScene::set_refit_nodes(const std::vector<BvhNode>& nodes) { impl_->refit_nodes.upload(nodes); }

std::vector<BvhNode> DeviceScene::download_refit_nodes() const { return impl_->refit_nodes.download(); }

RenderTimes DeviceScene::render(const FrameView<AmrVolume>& h, const float* device_values, const float* device_second) {
  Impl& m = *impl_;
  const Stopwatch watch;
  FrameView<AmrVolume> d = m.device_view(h);
  m.sync();
  const double upload = watch.seconds();
  d.volume.amr = m.view(device_values);
  d.volume.fields[0] = device_values;
  d.volume.fields[1] = device_second;
  d.volume.nodes = m.refit_nodes.data();
  d.volume.wide_nodes = nullptr;  // the CPU's walk; the GPU walks the binary tree
  d.volume.wide_node_count = 0;
  d.volume.node_count = uint32_t(m.refit_nodes.size());
  d.volume.all_nodes = m.template_nodes.data();
  d.volume.all_node_count = uint32_t(m.template_nodes.size());
  d.volume.sample_bricks = nullptr;  // host records: the GPU samples with the reference sampler
  return m.render(h, d, upload);
}

void DeviceScene::set_blocks(const KdBlocks& kd) {
  impl_->kd_nodes.upload(kd.nodes);
  impl_->blocks.upload(kd.blocks);
}

void DeviceScene::set_vertex_fields(const VertexField* primary, const VertexField* second) {
  Impl& m = *impl_;
  const VertexField* fields[kVolumeFields] = {primary, second};
  m.vertex_offsets.upload(primary ? primary->offsets : std::vector<uint64_t>{});
  for (int f = 0; f < kVolumeFields; ++f)
    m.vertex_fields[f].upload(fields[f] ? fields[f]->values : std::vector<float>{});
}

RenderTimes DeviceScene::render(const FrameView<BlockVolume>& h, const float* device_values,
                                const float* device_second) {
  Impl& m = *impl_;
  if (m.blocks.size() != h.volume.kd.block_count)
    throw std::logic_error("DeviceScene: set_blocks() before rendering blocks");
  const Stopwatch watch;
  FrameView<BlockVolume> d = m.device_view(h);
  m.sync();
  const double upload = watch.seconds();
  BlockVolume& v = d.volume;
  v.kd.nodes = m.kd_nodes.data();
  v.kd.blocks = m.blocks.data();
  v.bricks = m.bricks.data();
  v.fields[0] = device_values;
  v.fields[1] = device_second;
  const bool vertices = h.volume.vertex_offsets != nullptr;
  v.vertex_offsets = vertices ? m.vertex_offsets.data() : nullptr;
  for (int f = 0; f < kVolumeFields; ++f)
    v.vertex_fields[f] = vertices && h.volume.vertex_fields[f] ? m.vertex_fields[f].data() : nullptr;
  return m.render(h, d, upload);
}

std::vector<float> DeviceScene::probe(const float* device_values, const std::vector<vec3f>& grid_points) {
  Impl& m = *impl_;
  DeviceBuffer<vec3f> points("probe points", grid_points);
  DeviceBuffer<float> out("probe points", grid_points.size());
  const AmrView view = m.view(device_values);
  const BvhNode* n = m.template_nodes.data();
  const uint32_t node_count = uint32_t(m.template_nodes.size());
  const vec3f* p = points.data();
  float* o = out.data();
  parallel_for(
      "probe", int64_t(grid_points.size()),
      [=] __device__(int64_t i) { o[i] = sample_point(view, n, node_count, p[i]); }, m.stream.s);
  m.sync();
  return out.download();
}

// ---------------------------------------------------------------------------------------------
struct DeviceValueBuffers::Impl {
  std::vector<DeviceBuffer<float>> buffers;  // "field values"
  uint64_t floats = 0;
  Stream stream;
};

DeviceValueBuffers::DeviceValueBuffers(int count, uint64_t floats_each) : impl_(std::make_unique<Impl>()) {
  impl_->floats = floats_each;
  for (int i = 0; i < count; ++i) impl_->buffers.emplace_back("field values", floats_each);
}

DeviceValueBuffers::~DeviceValueBuffers() = default;

const float* DeviceValueBuffers::data(int buffer) const { return impl_->buffers.at(size_t(buffer)).data(); }

void DeviceValueBuffers::upload(int buffer, const float* host, uint64_t floats) {
  DeviceBuffer<float>& b = impl_->buffers.at(size_t(buffer));
  if (floats > b.size()) throw std::logic_error("DeviceValueBuffers: upload larger than the buffer");
  VS_CUDA_CHECK(cudaMemcpyAsync(b.data(), host, floats * sizeof(float), cudaMemcpyHostToDevice, impl_->stream.s));
  impl_->stream.sync();
}

uint64_t DeviceValueBuffers::bytes() const { return impl_->buffers.size() * impl_->floats * sizeof(float); }

// ---------------------------------------------------------------------------------------------
RenderTimes render(const AmrTopology& topology, const FrameView<AmrVolume>& h) {
  const Stopwatch watch;
  DeviceScene scene(topology);
  const AmrVolume& vol = h.volume;
  scene.set_bvh(std::vector<BvhNode>(vol.all_nodes, vol.all_nodes + vol.all_node_count));
  scene.set_refit_nodes(std::vector<BvhNode>(vol.nodes, vol.nodes + vol.node_count));
  const bool second = vol.fields[1] != nullptr;
  DeviceValueBuffers values(second ? 2 : 1, topology.cell_count);
  values.upload(0, vol.fields[0], topology.cell_count);
  if (second) values.upload(1, vol.fields[1], topology.cell_count);
  const double upload = watch.seconds();
  RenderTimes times = scene.render(h, values.data(0), second ? values.data(1) : nullptr);
  times.upload_seconds += upload;
  return times;
}

}  // namespace vs::cuda
