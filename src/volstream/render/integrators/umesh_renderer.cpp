#include "volstream/render/integrators/umesh_renderer.h"

#include <algorithm>
#include <stdexcept>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/core/stopwatch.h"
#include "volstream/umesh/compact_store.h"

namespace vs {

void needs_reference_encoding(const std::string& feature) {
  throw UsageError("this dataset stores the compact mesh encoding; convert with --encoding reference for " + feature);
}

UMeshRenderer::UMeshRenderer(const UMesh& mesh, const MeshAccel& accel, const WorldTransform& transform,
                             const MeshWhole* whole, const MacroCells* cells)
    : UMeshRenderer(&mesh, nullptr, &accel, nullptr, transform, whole, cells) {}

UMeshRenderer::UMeshRenderer(const UMesh& mesh, const WorldTransform& transform)
    : UMeshRenderer(&mesh, std::make_unique<MeshAccel>(build_mesh_accel(mesh)), nullptr, nullptr, transform, nullptr,
                    nullptr) {}

UMeshRenderer::UMeshRenderer(const CompactMesh& stored, const WorldTransform& transform, const MeshWhole* whole,
                             const MacroCells* cells)
    : UMeshRenderer(nullptr, nullptr, nullptr, &stored, transform, whole, cells) {}

UMeshRenderer::UMeshRenderer(const UMesh* mesh, std::unique_ptr<MeshAccel> owned, const MeshAccel* borrowed,
                             const CompactMesh* stored, const WorldTransform& transform, const MeshWhole* whole,
                             const MacroCells* cells)
    : mesh_(mesh),
      owned_(std::move(owned)),
      accel_(borrowed ? borrowed : owned_.get()),
      stored_(stored),
      transform_(transform),
      bounds_(whole ? whole->world_bounds : world_bounds(mesh ? mesh->vertices : stored->vertices, transform)) {
  Stopwatch watch;
  const MacroGrid* grid = whole ? &whole->grid : nullptr;
  if (cells && !whole)
    cells_ = *cells;
  else
    cells_ = mesh ? build_macrocells(*mesh, grid) : build_macrocells(*stored, grid);
  build_seconds_ = watch.seconds();
  visible_.assign(cells_.region_count(), 1);
  walk_starts_.assign(cells_.region_count(), UMeshVolume::kWalkStartUnknown);
  shown_block();
  const UMeshBytes b = bytes();
  // The BVH and adjacency are the dataset's ("mesh") unless built here.
  const uint64_t accel = owned_ ? b.bvh_nodes + b.bvh_items + b.face_neighbors : 0;
  counted_ = CountedBytes("mesh macrocells", MemorySpace::host, int64_t(accel + b.macrocells));
}

std::vector<Range> UMeshRenderer::ranges(const float* values) {
  // Counts to 2 only (a series may run for ever); never where the lists were given.
  if (!region_vertices_ && ranges_calls_ < 2 && ++ranges_calls_ == 2) {
    std::optional<RegionVertices> built = mesh_ ? region_vertices(*mesh_, cells_) : region_vertices(*stored_, cells_);
    if (built) keep_region_vertices(std::move(*built));
  }
  if (region_vertices_) return macrocell_ranges(*region_vertices_, values);
  return mesh_ ? macrocell_ranges(*mesh_, cells_, values) : macrocell_ranges(*stored_, cells_, values);
}

void UMeshRenderer::take_region_vertices(const RegionVertices& lists) {
  if (lists.first.size() != cells_.region_count() + 1)
    throw std::logic_error("UMeshRenderer::take_region_vertices: lists of other macrocells");
  keep_region_vertices(lists);
}

void UMeshRenderer::keep_region_vertices(RegionVertices lists) {
  region_vertices_counted_ = CountedBytes("mesh region vertices", MemorySpace::host, int64_t(lists.bytes()));
  region_vertices_ = std::move(lists);
}

uint64_t UMeshRenderer::classify(const std::vector<Range>& ranges, const TransferTable& tf,
                                 const IntegratorSettings& iso, bool skip, SkipStats* stats) {
  return refit(regions_to_keep(ranges, region_count(), tf, iso, skip, stats), stats);
}

uint64_t UMeshRenderer::refit(const std::vector<uint8_t>& keep, SkipStats* stats) {
  Stopwatch watch;
  if (keep.empty())
    std::fill(visible_.begin(), visible_.end(), uint8_t(1));
  else if (keep.size() == visible_.size())
    std::copy(keep.begin(), keep.end(), visible_.begin());
  else
    throw std::invalid_argument("one flag per macrocell expected");
  const uint64_t visible = uint64_t(std::count(visible_.begin(), visible_.end(), uint8_t(1)));
  shown_block();
  if (stats) {
    stats->refit_seconds = watch.seconds();
    stats->visible = visible;
  }
  return visible;
}

// The smallest block of grid cells that holds every visible macrocell (none: lo > hi), which rays
// walk instead of the whole grid (MeshVolume::shown_lo).
void UMeshRenderer::shown_block() {
  shown_lo_ = cells_.grid.dims, shown_hi_ = vec3i(-1, -1, -1);
  for (size_t r = 0; r < visible_.size(); ++r) {
    if (!visible_[r]) continue;
    const vec3i cell = cells_.grid.cell_at(cells_.cell_of_region[r]);
    for (int a = 0; a < 3; ++a)
      shown_lo_[a] = std::min(shown_lo_[a], cell[a]), shown_hi_[a] = std::max(shown_hi_[a], cell[a]);
  }
}

const MeshAccel& UMeshRenderer::reference_accel() const {
  if (!mesh_) needs_reference_encoding("the reference encoding's element BVH");
  return *accel_;
}

UMeshView UMeshRenderer::mesh_view(Device device) const {
  const MeshAccel& accel = reference_accel();  // refuses a stored compact mesh before mesh_ is read
  // The walk records are the CPU walk's alone: built on the first view that walks, so that info,
  // probes (no walk) and CUDA frames (the device walks by corners) do not pay 64 B an element.
  if (device == Device::cuda) return view_of(*mesh_, accel);
  std::call_once(*tet_walk_once_, [&] {
    tet_walk_ = accel.stored_tet_walk ? accel.stored_tet_walk(*mesh_, accel.neighbors)
                                      : tet_walk_records(*mesh_, accel.neighbors);
    tet_walk_counted_ =
        CountedBytes("tet walk records", MemorySpace::host, int64_t(tet_walk_.size() * sizeof(TetWalkRecord)));
  });
  UMeshView view = view_of(*mesh_, accel);
  view.tet_walk = tet_walk_.data();  // null without tets
  return view;
}

template <typename Locator>
FrameView<MeshVolume<Locator>> UMeshRenderer::make_view(const Locator& locator, const FrameFields& fields,
                                                        const OpticsView& optics, const TfView* color_tf,
                                                        const Camera& camera, const FrameSettings& settings) const {
  FrameView<MeshVolume<Locator>> v;
  v.volume.mesh = locator;
  v.volume.fields[0] = fields.primary;
  v.volume.fields[1] = fields.second;
  v.volume.visible = visible_.data();
  v.volume.step_widths = cells_.step_width.data();
  v.volume.grid = cells_.grid;
  v.volume.region_of_cell = cells_.region_of_cell.data();
  v.volume.shown_lo = shown_lo_, v.volume.shown_hi = shown_hi_;
  fill_frame(v, optics, color_tf, fields.second != nullptr, camera, settings, transform_, bounds_);
  // A ray crosses a macrocell every few samples: on a lattice the cells of one width march as one
  // interval (MeshVolume::for_each_interval) and none rounds its step count up (settings.h).
  v.settings.march = March::lattice;
  return v;
}

FrameView<UMeshVolume> UMeshRenderer::view(const FrameFields& fields, const OpticsView& optics, const TfView* color_tf,
                                           const Camera& camera, const FrameSettings& settings, Device device) const {
  FrameView<UMeshVolume> v = make_view(mesh_view(device), fields, optics, color_tf, camera, settings);
  if (device == Device::cpu) {
    v.volume.walk_starts = walk_starts_.data();
    v.volume.mesh.occupancy = occupancy();
  }
  return v;
}

const CompactMesh& UMeshRenderer::compact() {
  if (stored_) return *stored_;
  if (!compact_) {
    compact_ = std::make_unique<CompactMesh>(build_compact_mesh(*mesh_));
    const CompactBytes b = compact_->bytes_by_part();
    compact_counted_ = CountedBytes("compact mesh", MemorySpace::host,
                                    int64_t(b.total() - b.field + compact_->source_vertex.size() * sizeof(uint32_t)));
  }
  return *compact_;
}

CompactMeshView UMeshRenderer::compact_view() {
  CompactMeshView view = view_of(compact());
  view.occupancy = occupancy();
  return view;
}

SubcellOccupancy UMeshRenderer::occupancy() const {
  const MacroCells::SubcellMasks& s = cells_.subcells;
  if (s.of_region.size() != cells_.region_count()) return {};
  return {cells_.grid, cells_.region_of_cell.data(), s.of_region.data(), s.masks.data()};
}

const float* UMeshRenderer::compact_values(const float* values, std::vector<float>& storage) {
  if (stored_ || !values) return values;
  storage = compact().gather(values);
  return storage.data();
}

FrameView<CompactMeshVolume> UMeshRenderer::view_compact(const FrameFields& local_fields, const OpticsView& optics,
                                                         const TfView* color_tf, const Camera& camera,
                                                         const FrameSettings& settings) {
  return make_view(compact_view(), local_fields, optics, color_tf, camera, settings);
}

std::vector<float> UMeshRenderer::probe_compact(const float* values, const std::vector<vec3f>& points) {
  const CompactMeshView view = compact_view();
  std::vector<float> storage;
  const float* local = compact_values(values, storage);
  std::vector<float> out(points.size());
  parallel_for("probe", int64_t(points.size()),
               [&](int64_t i) { out[size_t(i)] = view.sample(local, points[size_t(i)]); });
  return out;
}

std::vector<float> UMeshRenderer::probe(const float* values, const std::vector<vec3f>& points) const {
  UMeshView view = view_of(*mesh_, reference_accel());  // a search per point: no walk
  view.occupancy = occupancy();
  std::vector<float> out(points.size());
  parallel_for("probe", int64_t(points.size()),
               [&](int64_t i) { out[size_t(i)] = view.sample(values, points[size_t(i)]); });
  return out;
}

UMeshBytes UMeshRenderer::bytes() const {
  UMeshBytes b;
  if (mesh_) {
    b.vertices = mesh_->vertices.size() * sizeof(vec3f);
    b.elements = mesh_->elements.size() * sizeof(UElement);
    b.bvh_nodes = accel_->bvh.nodes.size() * sizeof(ElementBvhNode);
    b.face_neighbors = accel_->neighbors.size() * sizeof(uint32_t);
    b.bvh_items = accel_->bvh.items.size() * sizeof(uint32_t);
    b.tet_walk = has_tets(*mesh_) ? mesh_->elements.size() * sizeof(TetWalkRecord) : 0;  // once a CPU frame walks
    b.field = mesh_->vertices.size() * sizeof(float);
  } else {
    b.compact = stored_->bytes_by_part();
    b.field = b.compact.field;
    b.compact.field = 0;
  }
  // With what a frame keeps per macrocell: one field's value range and the visible flag.
  b.macrocells = cells_.bytes() + cells_.region_count() * (sizeof(Range) + sizeof(uint8_t) + sizeof(uint32_t));
  if (region_vertices_) b.region_lists = region_vertices_->bytes();
  return b;
}

std::vector<double> probe_brute_force(const CompactMesh& mesh, const float* local_values,
                                      const std::vector<vec3f>& points) {
  const CompactMeshView view = view_of(mesh);
  std::vector<double> out(points.size(), NAN);
  parallel_for("probe_brute_force", int64_t(points.size()), [&](int64_t i) {
    CompactMeshView::Hit hit;
    float best = INFINITY;
    for (uint32_t l = 0; l < view.leaf_count; ++l)
      if (view.test_leaf(l, points[size_t(i)], hit, best)) break;
    if (hit.leaf < 0) return;
    double f = 0;
    for (int k = 0; k < hit.n; ++k) f += double(hit.w[k]) * double(local_values[hit.first_vertex + hit.v[k]]);
    out[size_t(i)] = f;
  });
  return out;
}

std::vector<double> probe_brute_force(const UMesh& mesh, const float* values, const std::vector<vec3f>& points) {
  UMeshView view;  // no BVH and no walk: only the elements' tests
  view.vertices = mesh.vertices.data();
  view.elements = mesh.elements.data();
  std::vector<double> out(points.size(), NAN);
  parallel_for("probe_brute_force", int64_t(points.size()), [&](int64_t i) {
    ElementHit hit;
    float best = INFINITY;
    for (uint32_t e = 0; e < mesh.elements.size(); ++e)
      if (view.consider(e, points[size_t(i)], hit, best)) break;
    if (hit.element < 0) return;
    const UElement& el = mesh.elements[size_t(hit.element)];
    double f = 0;
    for (int k = 0; k < el.vertex_count(); ++k) f += double(hit.w[k]) * double(values[el.v[k]]);
    out[size_t(i)] = f;
  });
  return out;
}

}  // namespace vs
