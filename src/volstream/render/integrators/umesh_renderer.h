// The host side of unstructured-mesh rendering (issue 12, reference encoding): the element BVH
// for point location and the macrocells for the march are built once; per step the macrocells'
// value ranges are recomputed (only scalars change) and classified, as for ABRs. Rays walk the
// macrocell grid (umesh/macrocells.h), so the pipeline's `refit` stage only sets one visible
// flag per macrocell: there is no region BVH. The one integrator (integrator.h) runs over
// UMeshVolume.
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "volstream/amr/source.h"
#include "volstream/backend/memory.h"
#include "volstream/render/integrators/abr_renderer.h"
#include "volstream/render/skipping.h"
#include "volstream/umesh/adjacency.h"
#include "volstream/umesh/compact.h"
#include "volstream/umesh/element_bvh.h"
#include "volstream/umesh/macrocells.h"
#include "volstream/umesh/mesh_accel.h"
#include "volstream/volume/umesh_volume.h"

namespace vs {

// Resident bytes of each structure the renderer keeps for a mesh (info, bytes_per_element): the
// reference encoding's parts, or the stored compact encoding's (`compact`, its field excluded).
struct UMeshBytes {
  uint64_t vertices = 0, elements = 0, bvh_nodes = 0, bvh_items = 0, face_neighbors = 0, tet_walk = 0, macrocells = 0,
           field = 0;
  uint64_t region_lists = 0;  // the macrocells' vertex lists, where given (take_region_vertices)
  CompactBytes compact;
  uint64_t total() const {
    return vertices + elements + bvh_nodes + bvh_items + face_neighbors + tet_walk + macrocells + region_lists + field +
           compact.total();
  }
};

// A data-parallel rank's share of a mesh (mpi/mesh_share.h) is rendered with the whole mesh's
// macrocell grid and world bounds (the default reference step), so that where the rank holds
// every element of a macrocell, that region and its steps are the one process's.
struct MeshWhole {
  MacroGrid grid;
  Box3<double> world_bounds;
};

class UMeshRenderer {
 public:
  // Keeps references to `mesh` and `accel` (the dataset's stored BVH and adjacency). With `cells`
  // (this whole mesh's, as the dataset built them at load: Dataset::macrocells) they are copied,
  // not built; with `whole` (a part's) they are built over the part on the whole grid.
  UMeshRenderer(const UMesh& mesh, const MeshAccel& accel, const WorldTransform& transform,
                const MeshWhole* whole = nullptr, const MacroCells* cells = nullptr);
  // Builds its own BVH and adjacency (tests, meshes not read from a dataset).
  UMeshRenderer(const UMesh& mesh, const WorldTransform& transform);
  // A mesh stored in the compact encoding (keeps a reference): no reference encoding exists, so
  // only the compact views and probes work, and values are per local vertex.
  UMeshRenderer(const CompactMesh& stored, const WorldTransform& transform, const MeshWhole* whole = nullptr,
                const MacroCells* cells = nullptr);
  bool has_reference() const { return mesh_ != nullptr; }

  // Values as the dataset stores them: per vertex (reference) or per local vertex (compact). With
  // the region vertex lists given (take_region_vertices), every call reads them; else the first
  // call (one frame) passes over the elements and the second (a time series) builds the lists once
  // (RegionVertices, unless over their budget), which this and every later call read instead.
  std::vector<Range> ranges(const float* values);
  // The vertex lists of these macrocells (a dataset's stored ones, checked against its mesh:
  // Dataset::region_vertices); kept as a view of the same memory.
  void take_region_vertices(const RegionVertices& lists);
  // Classifies the macrocells by their ranges (skip = false keeps every one); returns the visible ones.
  uint64_t classify(const std::vector<Range>& ranges, const TransferTable& tf, const IntegratorSettings& iso, bool skip,
                    SkipStats* stats = nullptr);
  // Keeps the macrocells with keep[i] != 0 (empty: all); returns the visible ones.
  uint64_t refit(const std::vector<uint8_t>& keep, SkipStats* stats = nullptr);

  // For `device`'s kernel: a CUDA frame's view has no walk records (mesh_view) and no walk starts.
  FrameView<UMeshVolume> view(const FrameFields& fields, const OpticsView& optics, const TfView* color_tf,
                              const Camera& camera, const FrameSettings& settings, Device device = Device::cpu) const;
  Image render(const FrameView<UMeshVolume>& view, FrameStats* stats = nullptr) const {
    return render_view_cpu(view, stats);
  }
  // Field values at grid points through the element BVH, NaN outside every element.
  std::vector<float> probe(const float* values, const std::vector<vec3f>& grid_points) const;

  // Paper 002's compact encoding (umesh/compact.h): the stored one, or built from the reference
  // mesh on first use. Its view takes fields per local vertex (compact_values), the macrocells
  // and skipping are shared.
  const CompactMesh& compact();
  // Values as the dataset stores them, per local vertex: themselves for a stored compact mesh,
  // else gathered into `storage`.
  const float* compact_values(const float* values, std::vector<float>& storage);
  FrameView<CompactMeshVolume> view_compact(const FrameFields& local_fields, const OpticsView& optics,
                                            const TfView* color_tf, const Camera& camera,
                                            const FrameSettings& settings);
  std::vector<float> probe_compact(const float* values, const std::vector<vec3f>& grid_points);  // stored order

  // The reference encoding's locator; for the CPU with the tets' walk records (built on the first
  // such call), for CUDA without (the device walks by corners, and gets the mesh's own arrays).
  UMeshView mesh_view(Device device = Device::cpu) const;
  const MacroCells& macrocells() const { return cells_; }
  const ElementBvh& element_bvh() const { return reference_accel().bvh; }
  const HostArray<uint32_t>& face_neighbors() const { return reference_accel().neighbors; }
  size_t region_count() const { return cells_.region_count(); }
  UMeshBytes bytes() const;
  double build_seconds() const { return build_seconds_; }

 private:
  UMeshRenderer(const UMesh* mesh, std::unique_ptr<MeshAccel> owned, const MeshAccel* borrowed,
                const CompactMesh* stored, const WorldTransform& transform, const MeshWhole* whole,
                const MacroCells* cells);
  const MeshAccel& reference_accel() const;  // UsageError for a stored compact mesh
  template <typename Locator>
  FrameView<MeshVolume<Locator>> make_view(const Locator& locator, const FrameFields& fields, const OpticsView& optics,
                                           const TfView* color_tf, const Camera& camera,
                                           const FrameSettings& settings) const;
  CompactMeshView compact_view();
  // The macrocells' subcell masks for a CPU sampler (SubcellOccupancy); none where not built.
  SubcellOccupancy occupancy() const;
  void shown_block();                               // shown_lo_, shown_hi_ from visible_
  void keep_region_vertices(RegionVertices lists);  // and counts their bytes
  const UMesh* mesh_;                               // null for a stored compact mesh
  std::unique_ptr<MeshAccel> owned_;                // when built here
  const MeshAccel* accel_;                          // with mesh_
  const CompactMesh* stored_;                       // a stored compact mesh
  WorldTransform transform_;
  Box3<double> bounds_;  // world box of the vertices (the default reference step), once per mesh
  double build_seconds_ = 0;
  MacroCells cells_;
  int ranges_calls_ = 0;                           // 0, 1, then 2 from the second call on
  std::optional<RegionVertices> region_vertices_;  // from the second ranges() call
  CountedBytes region_vertices_counted_;
  std::vector<uint8_t> visible_;  // per macrocell, from classify or refit
  vec3i shown_lo_, shown_hi_;     // the block of grid cells holding the visible ones (refit)
  // Per macrocell, where a ray's first sample walks from (MeshVolume::walk_starts): CPU frames
  // of the reference encoding fill it as rays need it, kept for the mesh's later frames.
  mutable std::vector<uint32_t> walk_starts_;
  // Per element where the mesh has tets (element_bvh.h), built by the first mesh_view().
  mutable TetWalkRecords tet_walk_;
  mutable CountedBytes tet_walk_counted_;
  std::unique_ptr<std::once_flag> tet_walk_once_ = std::make_unique<std::once_flag>();
  CountedBytes counted_;
  std::unique_ptr<CompactMesh> compact_;
  CountedBytes compact_counted_;
};

// The reference for probe(): every element tested for every point (no BVH), double precision
// interpolation of the weights found.
std::vector<double> probe_brute_force(const UMesh& mesh, const float* values, const std::vector<vec3f>& grid_points);
// The same over every decoded element of a compact mesh (no BVH, no walk), values per local vertex.
std::vector<double> probe_brute_force(const CompactMesh& mesh, const float* local_values,
                                      const std::vector<vec3f>& grid_points);

// The one line for a feature that needs the reference encoding on a dataset stored compact.
[[noreturn]] void needs_reference_encoding(const std::string& feature);

}  // namespace vs
