// Without the CUDA backend: no device, and asking for one is a clear error.
#ifndef VOLSTREAM_HAVE_CUDA
#include <stdexcept>

#include "volstream/cuda/backend.h"

namespace vs::cuda {
namespace {
[[noreturn]] void no_cuda() { throw std::runtime_error("this volstream was built without CUDA"); }
}  // namespace

struct DeviceScene::Impl {};
struct DeviceValueBuffers::Impl {};

bool cuda_available() { return false; }
std::string device_name() { return {}; }
std::vector<float> probe_points(const AmrTopology&, const Bvh&, const float*, const std::vector<vec3f>&) { no_cuda(); }
RenderTimes render(const AmrTopology&, const FrameView<AmrVolume>&) { no_cuda(); }

DeviceScene::DeviceScene(const AmrTopology&) { no_cuda(); }
DeviceScene::~DeviceScene() = default;
void DeviceScene::set_bvh(const std::vector<BvhNode>&) { no_cuda(); }
void DeviceScene::compute_ranges(const float*) { no_cuda(); }
std::vector<Range> DeviceScene::download_ranges() const { no_cuda(); }
uint64_t DeviceScene::classify_and_refit(const TransferTable&, const IntegratorSettings&, bool) { no_cuda(); }
void DeviceScene::set_refit_nodes(const std::vector<BvhNode>&) { no_cuda(); }
std::vector<BvhNode> DeviceScene::download_refit_nodes() const { no_cuda(); }
RenderTimes DeviceScene::render(const FrameView<AmrVolume>&, const float*, const float*) { no_cuda(); }
void DeviceScene::set_blocks(const KdBlocks&) { no_cuda(); }
void DeviceScene::set_vertex_fields(const VertexField*, const VertexField*) { no_cuda(); }
RenderTimes DeviceScene::render(const FrameView<BlockVolume>&, const float*, const float*) { no_cuda(); }
std::vector<float> DeviceScene::probe(const float*, const std::vector<vec3f>&) { no_cuda(); }

DeviceValueBuffers::DeviceValueBuffers(int, uint64_t) { no_cuda(); }
DeviceValueBuffers::~DeviceValueBuffers() = default;
const float* DeviceValueBuffers::data(int) const { no_cuda(); }
void DeviceValueBuffers::upload(int, const float*, uint64_t) { no_cuda(); }
uint64_t DeviceValueBuffers::bytes() const { no_cuda(); }
}  // namespace vs::cuda
#endif
