#include "volstream/frame/frame_renderer.h"

#include <cmath>
#include <numeric>

#include <tbb/parallel_invoke.h>

#include "volstream/amr/probe.h"
#include "volstream/backend/backend.h"
#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/core/stopwatch.h"
#include "volstream/cuda/backend.h"
#include "volstream/cuda/umesh_backend.h"
#include "volstream/frame/look.h"
#include "volstream/io/image.h"
#include "volstream/render/integrators/umesh_renderer.h"

namespace vs {
namespace {

bool same_spec(const TransferFunctionSpec& a, const TransferFunctionSpec& b) {
  auto same_colors = [](const std::vector<ColorPoint>& x, const std::vector<ColorPoint>& y) {
    return std::equal(x.begin(), x.end(), y.begin(), y.end(), [](const ColorPoint& p, const ColorPoint& q) {
      return p.x == q.x && p.r == q.r && p.g == q.g && p.b == q.b;
    });
  };
  auto same_opacity = [](const std::vector<OpacityPoint>& x, const std::vector<OpacityPoint>& y) {
    return std::equal(x.begin(), x.end(), y.begin(), y.end(),
                      [](const OpacityPoint& p, const OpacityPoint& q) { return p.x == q.x && p.a == q.a; });
  };
  return a.lo == b.lo && a.hi == b.hi && a.log_scale == b.log_scale && same_colors(a.colors, b.colors) &&
         same_opacity(a.opacity, b.opacity);
}

bool same_iso(const IntegratorSettings& a, const IntegratorSettings& b) {
  if (a.iso_count != b.iso_count) return false;
  for (uint32_t i = 0; i < a.iso_count && i < kMaxIso; ++i)
    if (a.iso[i] != b.iso[i]) return false;
  return true;
}

// A transfer table rebuilt only when its spec changes.
struct CachedTable {
  std::unique_ptr<TransferTable> table;
  const TransferTable& get(const TransferFunctionSpec& spec) {
    if (!table || !same_spec(table->spec(), spec)) table = std::make_unique<TransferTable>(spec);
    return *table;
  }
};

// The values of one field at one step: read into host memory (and uploaded on CUDA), or handed
// over by the streaming pipeline. `generation` changes whenever the values do.
struct FieldSlot {
  int field = -1, step = -1;
  std::vector<float> host;
  CountedBytes counted{"field values", MemorySpace::host};
  const float* external = nullptr;  // use_values(): host or device memory of the caller
  uint64_t generation = 0;
};

// The ABRs where the blackbody model has something to emit or absorb: some density whose
// normalised value is above 0 (blackbody.h), with a margin for float rounding.
std::vector<uint8_t> blackbody_keep(const std::vector<Range>& ranges, const FrameRequest& r) {
  if (!r.skip) return {};
  const BlackbodyParams& p = r.blackbody;
  const double threshold = p.log_decades > 0.f ? 0.999 * p.rho_max * std::pow(10.0, -double(p.log_decades)) : 0.0;
  std::vector<uint8_t> keep(ranges.size());
  for (size_t i = 0; i < ranges.size(); ++i) keep[i] = ranges[i].lo <= ranges[i].hi && ranges[i].hi > threshold ? 1 : 0;
  return keep;
}

}  // namespace

struct FrameRenderer::Impl {
  const Dataset& dataset;
  Device device;
  Backend backend;
  FieldSlot slots[kVolumeFields];
  uint64_t next_generation = 1;

  std::unique_ptr<AmrRenderer> abr;
  std::unique_ptr<cuda::DeviceScene> scene;  // CUDA: topology, BVHs, ranges, image
  std::vector<Buffer<float>> device_slots;   // CUDA: the slots' values on the device
  std::vector<uint64_t> macro_offset;        // CPU ranges (amr/ranges.h)
  std::vector<Range> ranges;                 // CPU (and stored ranges)
  CountedBytes ranges_bytes{"ABR ranges", MemorySpace::host};

  // What the current ranges and classification were made from (0: nothing yet).
  uint64_t ranges_generation = 0;
  RangeMode ranges_mode = RangeMode::tight;
  bool ranges_stored = false;
  uint64_t ranges_stamp = 0, classified_stamp = 0;
  TransferFunctionSpec classified_tf;
  IntegratorSettings classified_iso;
  bool classified_skip = true;
  OpticsKind classified_optics = OpticsKind::tf;
  BlackbodyParams classified_bb;

  std::unique_ptr<UMeshRenderer> umesh;                     // a mesh dataset: its BVH and macrocells
  std::unique_ptr<cuda::DeviceMesh> device_mesh;            // CUDA: the mesh, its BVH and macrocells
  std::unique_ptr<cuda::DeviceCompactMesh> device_compact;  // CUDA: a stored compact mesh

  std::unique_ptr<BlockRenderer> blocks;
  uint64_t block_generation[kVolumeFields] = {};
  bool block_vertices = false;

  CachedTable tf, color_tf;

  // One frame of a view (host pointers; the scene swaps in its device arrays) on the GPU.
  template <typename V>
  Image render_on_device(FrameView<V> view, FrameReport& report) {
    Image img(view.width, view.height);
    std::vector<uint32_t> counts(size_t(view.width) * view.height);
    view.rgba = img.rgba.data();
    view.sample_counts = counts.data();
    const cuda::RenderTimes t = scene->render(view, kernel_values(0), kernel_values(1));
    report.seconds.upload += t.upload_seconds;
    report.seconds.render += t.kernel_seconds;
    report.samples = std::accumulate(counts.begin(), counts.end(), uint64_t(0));
    return img;
  }

  Impl(const Dataset& ds, Device d) : dataset(ds), device(d), backend(d) {
    if (d == Device::cuda)
      for (int s = 0; s < kVolumeFields; ++s) device_slots.push_back(backend.buffer<float>("field values"));
  }

  UMeshRenderer& umesh_renderer() {
    if (!umesh) {
      const WorldTransform& transform = dataset.manifest().transform;
      const DatasetPart* part = dataset.part();
      MeshWhole whole;
      if (part) whole = {part->mesh_grid, part->world_bounds};
      const MeshWhole* share = part ? &whole : nullptr;
      const MacroCells* stored = dataset.macrocells();
      umesh = dataset.is_compact_mesh()
                  ? std::make_unique<UMeshRenderer>(dataset.compact_mesh(), transform, share, stored)
                  : std::make_unique<UMeshRenderer>(dataset.mesh(), dataset.mesh_accel(), transform, share, stored);
      if (const RegionVertices* lists = dataset.region_vertices(); lists && stored) umesh->take_region_vertices(*lists);
      device_mesh.reset();
      device_compact.reset();
    }
    return *umesh;
  }
  // The encoding that samples a request: the stored one unless it asks for another; a compact
  // dataset has no reference encoding to sample.
  MeshEncoding sampled_encoding(MeshEncoding requested) const {
    const MeshEncoding stored = dataset.manifest().mesh.encoding;
    if (requested == MeshEncoding::stored) return stored;
    if (requested == MeshEncoding::reference && stored == MeshEncoding::compact)
      needs_reference_encoding("render or probe --encoding reference");
    return requested;
  }
  // On CUDA the compact encoding samples the values the dataset stores per local vertex (uploaded
  // like any field); one built at load from a reference dataset is sampled on the CPU only.
  void check_compact_device(const char* what) const {
    if (device == Device::cpu || dataset.is_compact_mesh()) return;
    throw UsageError(std::string("the compact mesh encoding built at load ") + what +
                     " on the CPU only (convert with --encoding compact for CUDA)");
  }
  // The slots' values per local vertex of the compact encoding (gathered when they change, unless
  // the dataset stores them so).
  std::vector<float> compact_storage[kVolumeFields];
  const float* compact_values[kVolumeFields] = {};
  uint64_t compact_generation[kVolumeFields] = {};
  void update_compact_fields() {
    for (int s = 0; s < kVolumeFields; ++s) {
      if (compact_generation[s] == slots[s].generation) continue;
      compact_values[s] = umesh->compact_values(host_values(s), compact_storage[s]);
      compact_generation[s] = slots[s].generation;
    }
  }
  cuda::DeviceMesh& mesh_on_device() {
    UMeshRenderer& mesh = umesh_renderer();
    if (!device_mesh)
      device_mesh = std::make_unique<cuda::DeviceMesh>(dataset.mesh(), mesh.element_bvh(), mesh.face_neighbors(),
                                                       mesh.macrocells());
    return *device_mesh;
  }
  cuda::DeviceCompactMesh& compact_on_device() {
    UMeshRenderer& mesh = umesh_renderer();
    if (!device_compact) device_compact = std::make_unique<cuda::DeviceCompactMesh>(mesh.compact(), mesh.macrocells());
    return *device_compact;
  }
  auto& on_device(const UMeshVolume*) { return mesh_on_device(); }
  auto& on_device(const CompactMeshVolume*) { return compact_on_device(); }
  // A mesh frame of either encoding: on the CPU, or on the GPU through the same kernel source.
  template <typename Volume>
  Image render_mesh(const FrameView<Volume>& host_view, FrameReport& report) {
    if (device == Device::cpu) {
      FrameStats stats;
      Image img = render_view_cpu(host_view, &stats);
      report.seconds.render += stats.render_seconds;
      report.samples = stats.samples;
      return img;
    }
    FrameView<Volume> view = host_view;
    Image img(view.width, view.height);
    std::vector<uint32_t> counts(size_t(view.width) * view.height);
    view.rgba = img.rgba.data();
    view.sample_counts = counts.data();
    const cuda::RenderTimes t = on_device(static_cast<const Volume*>(nullptr)).render(view);
    report.seconds.upload += t.upload_seconds;
    report.seconds.render += t.kernel_seconds;
    report.samples = std::accumulate(counts.begin(), counts.end(), uint64_t(0));
    return img;
  }
  // A mesh frame's classification (ranges as for ABRs; the blackbody model by density).
  uint64_t classify_mesh(const FrameRequest& r, const TransferTable& table, FrameStats& stats) {
    SkipStats s;
    const uint64_t visible = r.optics == OpticsKind::blackbody
                                 ? umesh_renderer().refit(blackbody_keep(ranges, r), &s)
                                 : umesh_renderer().classify(ranges, table, r.integrator, r.skip, &s);
    stats.classify_seconds = s.classify_seconds;
    stats.refit_seconds = s.refit_seconds;
    return visible;
  }

  AmrRenderer& abr_renderer() {
    if (!abr) build_abr();
    return *abr;
  }
  cuda::DeviceScene& device_scene() {
    if (!scene) scene = std::make_unique<cuda::DeviceScene>(dataset.topology());
    return *scene;
  }
  void build_abr() {
    abr = std::make_unique<AmrRenderer>(dataset.topology(), dataset.manifest().transform, vs::world_bounds(dataset));
    if (device == Device::cuda) device_scene().set_bvh(abr->template_bvh().nodes);
    classified_stamp = 0;  // a fresh BVH is not refit yet
  }
  BlockRenderer& block_renderer() {
    if (!blocks) {
      blocks = std::make_unique<BlockRenderer>(dataset.topology(), dataset.manifest().transform);
      if (device == Device::cuda) device_scene().set_blocks(blocks->kd());
    }
    return *blocks;
  }
  // The block renderer's fields (and vertex values for trilinear) follow the slots; true when
  // they were (re)built.
  bool update_block_fields(bool vertices) {
    if (block_generation[0] == slots[0].generation && block_generation[1] == slots[1].generation &&
        (!vertices || block_vertices))
      return false;
    BlockRenderer& b = block_renderer();
    b.set_fields(host_values(0), host_values(1), vertices);
    if (device == Device::cuda) device_scene().set_vertex_fields(b.vertex_field(0), b.vertex_field(1));
    block_generation[0] = slots[0].generation;
    block_generation[1] = slots[1].generation;
    block_vertices = vertices;
    return true;
  }

  // The values of slot s in the memory the kernels read (device memory on CUDA).
  const float* kernel_values(int s) const {
    const FieldSlot& slot = slots[s];
    if (slot.external) return slot.external;
    if (slot.field < 0) return nullptr;
    return device == Device::cuda ? device_slots[size_t(s)].data() : slot.host.data();
  }
  const float* host_values(int s) const {
    const FieldSlot& slot = slots[s];
    if (slot.field < 0 && !slot.external) return nullptr;
    if (slot.external && device == Device::cuda)
      throw UsageError("meshes and the block integrator on CUDA need the values in host memory (use render, not play)");
    return slot.external ? slot.external : slot.host.data();
  }

  void load(int s, int field, int step, FrameTimes& t) {
    FieldSlot& slot = slots[s];
    if (field < 0) {
      slot = {};
      return;
    }
    if (!slot.external && slot.field == field && slot.step == step) return;
    Stopwatch watch;
    slot.host = dataset.load_values(field, step);
    slot.counted.set(int64_t(slot.host.size() * sizeof(float)));
    slot.field = field;
    slot.step = step;
    slot.external = nullptr;
    slot.generation = next_generation++;
    t.read += watch.lap();
    if (device == Device::cuda) {
      device_slots[size_t(s)].upload(slot.host);
      t.upload += watch.lap();
    }
  }
};

FrameRenderer::FrameRenderer(const Dataset& dataset, Device device)
    : dataset_(dataset), device_(device), impl_(std::make_unique<Impl>(dataset, device)) {}

FrameRenderer::~FrameRenderer() = default;

Box3<double> FrameRenderer::world_bounds() const { return vs::world_bounds(dataset_); }

Camera FrameRenderer::default_camera(uint32_t width, uint32_t height) const {
  return default_view(dataset_, width, height);
}

void FrameRenderer::use_values(const float* primary) {
  FieldSlot& slot = impl_->slots[0];
  slot.external = primary;
  slot.host = {};
  slot.counted.set(0);
  slot.field = slot.step = -1;
  slot.generation = impl_->next_generation++;
  impl_->slots[1] = {};
}

void FrameRenderer::compute_ranges(const FrameRequest& r, FrameReport* report) {
  Impl& m = *impl_;
  if (r.kind != IntegratorKind::abr && !dataset_.is_mesh()) return;
  const uint64_t generation = m.slots[0].generation;
  const bool current = m.ranges_stamp && m.ranges_generation == generation && m.ranges_mode == r.range_mode &&
                       m.ranges_stored == r.stored_ranges;
  const bool cpu_ranges = !dataset_.is_mesh() && !r.stored_ranges && m.device == Device::cpu;
  if (dataset_.is_mesh())
    m.umesh_renderer();  // the element BVH and macrocells on first use
  else if (current || !cpu_ranges)
    m.abr_renderer();  // the BVH (and on CUDA the device scene) on first use
  if (current) return;
  double seconds = 0;
  const auto ranges = [&] {
    const Stopwatch watch;
    if (dataset_.is_mesh()) {
      m.ranges = m.umesh->ranges(m.host_values(0));  // host values: also on CUDA (ranges on the host)
    } else if (r.stored_ranges) {
      if (m.slots[0].field < 0) throw UsageError("stored ranges need a dataset step, not streamed values");
      m.ranges = m.dataset.load_abr_ranges(m.slots[0].field, m.slots[0].step);
    } else if (m.device == Device::cuda) {
      m.scene->compute_ranges(m.kernel_values(0));
    } else {
      if (m.macro_offset.empty()) m.macro_offset = macrocell_offsets(m.dataset.topology().bricks);
      m.ranges = compute_abr_ranges(m.dataset.topology(), m.kernel_values(0), &m.macro_offset, r.range_mode);
    }
    seconds = watch.seconds();
  };
  // A first frame's renderer set-up (the BVH's refit copy and 4-wide collapse, partly serial)
  // beside the CPU's ranges (parallel loops): they share no state. Jet 1e6: about 15 ms less.
  if (cpu_ranges && !m.abr)
    tbb::parallel_invoke([&] { m.abr_renderer(); }, ranges);
  else
    ranges();
  m.ranges_bytes.set(int64_t(m.ranges.size() * sizeof(Range) + m.macro_offset.size() * sizeof(uint64_t)));
  m.ranges_generation = generation;
  m.ranges_mode = r.range_mode;
  m.ranges_stored = r.stored_ranges;
  m.ranges_stamp = m.next_generation++;
  if (report) report->seconds.ranges += seconds;
}

void FrameRenderer::refit(const FrameRequest& r, bool rebuild, FrameReport* report) {
  Impl& m = *impl_;
  if (r.kind != IntegratorKind::abr && !dataset_.is_mesh()) return;
  if (rebuild && dataset_.is_mesh()) {
    Stopwatch watch;
    m.umesh.reset();  // what the pipeline levels before `refit` pay every frame
    m.umesh_renderer();
    m.classified_stamp = 0;
    if (report) report->seconds.refit += watch.seconds();
  } else if (rebuild) {
    Stopwatch watch;
    m.build_abr();  // what the pipeline levels before `refit` pay every frame
    if (report) report->seconds.refit += watch.seconds();
  }
  if (m.ranges_stamp == 0) return;  // no ranges yet: classified at the first frame
  if (m.classified_stamp == m.ranges_stamp && m.classified_skip == r.skip && same_iso(m.classified_iso, r.integrator) &&
      same_spec(m.classified_tf, r.tf) && m.classified_optics == r.optics &&
      m.classified_bb.rho_max == r.blackbody.rho_max && m.classified_bb.log_decades == r.blackbody.log_decades)
    return;
  const TransferTable& table = m.tf.get(r.tf);
  FrameStats stats;
  Stopwatch watch;
  if (dataset_.is_mesh()) {
    visible_ = m.classify_mesh(r, table, stats);
  } else if (r.optics == OpticsKind::blackbody) {
    AmrRenderer& abr = m.abr_renderer();
    // Emission and absorption depend on density alone, not on the transfer function's opacity.
    const bool device_ranges = m.device == Device::cuda && !r.stored_ranges;
    visible_ = abr.refit(blackbody_keep(device_ranges ? m.scene->download_ranges() : m.ranges, r), &stats);
    stats.classify_seconds = watch.seconds() - stats.refit_seconds;
    if (m.device == Device::cuda) m.scene->set_refit_nodes(abr.refit_nodes());
  } else if (m.device == Device::cuda && !r.stored_ranges) {
    visible_ = m.scene->classify_and_refit(table, r.integrator, r.skip);
    stats.refit_seconds = watch.seconds();
  } else {
    AmrRenderer& abr = m.abr_renderer();
    visible_ = abr.classify(m.ranges, table, r.integrator, r.skip, &stats);
    if (m.device == Device::cuda) m.scene->set_refit_nodes(abr.refit_nodes());
  }
  m.classified_stamp = m.ranges_stamp;
  m.classified_tf = r.tf;
  m.classified_iso = r.integrator;
  m.classified_skip = r.skip;
  m.classified_optics = r.optics;
  m.classified_bb = r.blackbody;
  if (report) {
    report->seconds.classify += stats.classify_seconds;
    report->seconds.refit += stats.refit_seconds;
  }
}

namespace {

BlockFrame block_frame(const FrameRequest& r) {
  BlockFrame f;
  f.width = r.width;
  f.height = r.height;
  f.settings.rate = r.integrator.rate;
  f.settings.ref_step = r.integrator.ref_step;
  f.settings.reconstruction = r.reconstruction;
  f.settings.optics = r.optics;
  f.blackbody = r.blackbody;
  f.integrator = r.integrator;
  return f;
}

FrameSettings frame_settings(const FrameRequest& r) {
  FrameSettings fs;
  fs.width = r.width;
  fs.height = r.height;
  fs.integrator = r.integrator;
  fs.integrator.march = March::equal_jittered;
  fs.skip = r.skip;
  fs.brick_ranges = r.range_mode == RangeMode::per_brick;
  return fs;
}

// A rank of a data-parallel frame (mpi/) composites only the light from its own region, and
// all of it: early termination would cut a ray where one process would not.
template <typename Volume>
void own_part(FrameView<Volume>& view, const DatasetPart* part) {
  if (!part) return;
  view.owned = {vec3f(part->owned.lower), vec3f(part->owned.upper)};
  view.settings.early_termination = 0;
}

}  // namespace

Image FrameRenderer::render_image(const FrameRequest& r, FrameReport* report) {
  Impl& m = *impl_;
  const TransferTable& table = m.tf.get(r.tf);
  const bool color_iso = r.optics == OpticsKind::tf && r.second_field >= 0;
  const TfView color_view = color_iso ? m.color_tf.get(r.color_tf).view() : TfView{};
  FrameReport local;
  local.device = m.device;
  Image img;
  OpticsView optics;
  optics.kind = r.optics;
  optics.tf = table.view();
  if (r.optics == OpticsKind::blackbody) optics.bb = default_blackbody_table().view(r.blackbody);
  if (dataset_.is_mesh()) {
    UMeshRenderer& mesh = m.umesh_renderer();
    const TfView* colors = color_iso ? &color_view : nullptr;
    if (m.sampled_encoding(r.mesh_encoding) == MeshEncoding::compact) {
      m.check_compact_device("renders");
      FrameFields fields{m.kernel_values(0), m.kernel_values(1)};  // a stored compact mesh's, per local vertex
      if (m.device == Device::cpu) {
        m.update_compact_fields();
        fields = {m.compact_values[0], m.compact_values[1]};
      }
      FrameView<CompactMeshVolume> view = mesh.view_compact(fields, optics, colors, r.camera, frame_settings(r));
      own_part(view, dataset_.part());
      img = m.render_mesh(view, local);
    } else {
      FrameView<UMeshVolume> view =
          mesh.view({m.kernel_values(0), m.kernel_values(1)}, optics, colors, r.camera, frame_settings(r), m.device);
      own_part(view, dataset_.part());
      img = m.render_mesh(view, local);
    }
    local.visible_regions = visible_;
    local.region_count = mesh.region_count();
  } else if (r.kind == IntegratorKind::blocks) {
    BlockRenderer& blocks = m.block_renderer();
    if (m.update_block_fields(r.reconstruction == Reconstruction::trilinear)) {
      local.vertex_seconds = blocks.vertex_seconds();
      local.seconds.ranges += local.vertex_seconds;
    }
    const TfView tf_view = table.view();
    if (m.device == Device::cuda) {
      img =
          m.render_on_device(blocks.view(&tf_view, r.camera, block_frame(r), color_iso ? &color_view : nullptr), local);
    } else {
      BlockStats bs;
      img = blocks.render(&tf_view, r.camera, block_frame(r), Device::cpu, &bs, color_iso ? &color_view : nullptr);
      local.seconds.render += bs.render_seconds;
      local.samples = bs.samples;
    }
    local.visible_regions = local.region_count = blocks.kd().blocks.size();
  } else {
    AmrRenderer& abr = m.abr_renderer();
    FrameView<AmrVolume> view = abr.view({m.kernel_values(0), m.kernel_values(1)}, optics,
                                         color_iso ? &color_view : nullptr, r.camera, frame_settings(r));
    own_part(view, dataset_.part());
    if (m.device == Device::cuda) {
      img = m.render_on_device(view, local);
    } else {
      FrameStats stats;
      img = abr.render(Device::cpu, view, &stats);
      local.seconds.render += stats.render_seconds;
      local.samples = stats.samples;
    }
    local.visible_regions = visible_;
    local.region_count = m.dataset.topology().abrs.size();
  }
  if (report) {
    report->device = local.device;
    report->seconds.upload += local.seconds.upload;
    report->seconds.ranges += local.seconds.ranges;
    report->seconds.render += local.seconds.render;
    report->samples = local.samples;
    report->visible_regions = local.visible_regions;
    report->region_count = local.region_count;
    report->vertex_seconds = local.vertex_seconds;
  }
  return img;
}

namespace {
std::vector<vec3f> grid_points(const WorldTransform& transform, const std::vector<vec3d>& world) {
  std::vector<vec3f> grid(world.size());
  for (size_t i = 0; i < world.size(); ++i) grid[i] = vec3f(transform.to_grid(world[i]));
  return grid;
}
}  // namespace

std::vector<float> FrameRenderer::probe(int field, int step, const std::vector<vec3d>& world,
                                        MeshEncoding mesh_encoding) {
  Impl& m = *impl_;
  FrameTimes ignored;
  m.load(0, field, step, ignored);
  const std::vector<vec3f> grid = grid_points(dataset_.manifest().transform, world);
  if (dataset_.is_mesh() && m.sampled_encoding(mesh_encoding) == MeshEncoding::compact) {
    m.check_compact_device("probes");
    return device_ == Device::cuda ? m.compact_on_device().probe(m.kernel_values(0), grid)
                                   : m.umesh_renderer().probe_compact(m.kernel_values(0), grid);
  }
  if (dataset_.is_mesh())
    return device_ == Device::cuda ? m.mesh_on_device().probe(m.kernel_values(0), grid)
                                   : m.umesh_renderer().probe(m.kernel_values(0), grid);
  const AmrRenderer& abr = m.abr_renderer();  // its BVH template locates the points
  if (device_ == Device::cuda) return m.device_scene().probe(m.kernel_values(0), grid);
  return probe_points(dataset_.topology(), abr.template_bvh(), m.kernel_values(0), grid);
}

Device resolve_device(const std::string& name, const Dataset& dataset, MeshEncoding encoding) {
  const bool compact_at_load = dataset.is_mesh() && !dataset.is_compact_mesh() && encoding == MeshEncoding::compact;
  return name == "auto" && compact_at_load ? Device::cpu : resolve_device(name);
}

std::vector<double> probe_brute_force(const Dataset& ds, int field, int step, const std::vector<vec3d>& world) {
  const std::vector<float> values = ds.load_values(field, step);
  if (ds.is_compact_mesh())  // values per local vertex
    return probe_brute_force(ds.compact_mesh(), values.data(), grid_points(ds.manifest().transform, world));
  if (ds.is_mesh()) return probe_brute_force(ds.mesh(), values.data(), grid_points(ds.manifest().transform, world));
  const std::vector<Cell> cells = ds.load_cells();
  std::vector<double> out(world.size());
  parallel_for("probe_brute_force", int64_t(world.size()), [&](int64_t i) {
    out[size_t(i)] = sample_brute_force(cells.data(), values.data(), cells.size(),
                                        ds.manifest().transform.to_grid(world[size_t(i)]));
  });
  return out;
}

std::vector<uint8_t> FrameRenderer::render_srgb8(const FrameRequest& r, const vec3f& background, FrameReport* report) {
  return to_rgb8(render(r, report), background);
}

Image FrameRenderer::render(const FrameRequest& r, FrameReport* report) {
  Impl& m = *impl_;
  const DatasetManifest& manifest = dataset_.manifest();
  if (r.step < 0 || r.step >= manifest.step_count())
    throw UsageError("step " + std::to_string(r.step) + " out of range 0.." +
                     std::to_string(manifest.step_count() - 1));
  if (r.optics == OpticsKind::blackbody && r.second_field < 0)
    throw UsageError("blackbody optics needs a temperature field");
  if (dataset_.is_mesh() && r.kind == IntegratorKind::blocks)
    throw UsageError("the block integrator is for AMR; a mesh is sampled through its elements");
  FrameReport local;
  m.load(0, r.field, r.step, local.seconds);
  m.load(1, r.second_field, r.step, local.seconds);
  compute_ranges(r, &local);
  refit(r, false, &local);
  Image img = render_image(r, &local);
  if (report) *report = local;
  return img;
}

}  // namespace vs
