// The native dataset directory (docs/formats.md): manifest.json, topology files, and one
// float32 file per (field, step) in device order, padded to 4 KiB, plus per-ABR value ranges.
// Optionally (`convert/demo --file-order`) a second copy of every step in file (source) order and
// the permutation `file_index.bin` from device to file order, for the streaming pipeline's
// per-frame flatten pass (docs/streaming.md).
#pragma once
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "volstream/amr/abrs.h"
#include "volstream/amr/model.h"
#include "volstream/amr/source.h"
#include "volstream/backend/memory.h"
#include "volstream/io/binary_file.h"
#include "volstream/umesh/compact.h"
#include "volstream/umesh/macrocells.h"
#include "volstream/umesh/mesh_accel.h"
#include "volstream/umesh/mesh_index.h"
#include "volstream/umesh/umesh.h"

namespace vs {

inline constexpr int kDatasetFormatVersion = 1;
inline constexpr uint64_t kFileAlignment = 4096;

inline uint64_t align_up(uint64_t n, uint64_t a = kFileAlignment) { return (n + a - 1) / a * a; }

struct FieldInfo {
  std::string name;
  std::string dir;                 // sub-directory name under fields/
  std::vector<Range> step_ranges;  // global min/max per step
};

struct LevelInfo {
  int32_t level;  // log2 width
  uint64_t cell_count;
};

// What a dataset holds: AMR cells (bricks, ABRs) or an unstructured mesh (umesh/umesh.h).
enum class DatasetKind { amr, umesh };

// How a mesh is stored and sampled: the reference encoding (umesh/umesh.h, with its element BVH
// and face adjacency) or paper 002's compact one (umesh/compact.h). `stored` (requests only):
// whichever the dataset holds.
enum class MeshEncoding { stored, reference, compact };
// "stored" | "reference" | "compact" (UsageError otherwise).
MeshEncoding parse_mesh_encoding(const std::string& name);

struct MeshCounts {
  uint64_t vertices = 0, elements = 0;
  uint64_t by_type[4] = {};  // umesh.h type_slot order: tetra, pyramid, wedge, hexahedron
  // The source's elements by type where convert split them into tets (umesh/split_tets.h;
  // manifest key "split_from", present only then); all 0 otherwise.
  uint64_t split_from[4] = {};
  bool split() const { return split_from[0] + split_from[1] + split_from[2] + split_from[3] > 0; }
  uint64_t bvh_nodes = 0;  // reference: element BVH nodes stored (mesh_accel.h)
  // reference: walk records stored in mesh_tet_walk.bin, one per element, or 0 where the mesh has
  // no tets (manifest key "tet_walk_records"; absent in older datasets, whose renders build them).
  uint64_t tet_walk_records = 0;
  // Manifest key "mesh_encoding" (absent in older datasets: reference).
  MeshEncoding encoding = MeshEncoding::reference;
  // compact: the records in each array file (umesh/compact_files.h), the local vertices (the
  // values per (field, step)) and the first node whose children are leaves.
  std::map<std::string, uint64_t> compact_records;
  uint64_t local_vertices = 0, leaf_parents = 0;
  // The non-empty macrocells in mesh_macrocells.bin (manifest key "macrocells"; absent in older
  // datasets: 0, no mesh index stored, and every rank reads the whole mesh).
  uint64_t macrocells = 0;
  // The macrocells' subcell masks (MacroCells::SubcellMasks) in mesh_subcells.bin: this many
  // masks, of the macrocells with an empty subcell (manifest key "subcell_masks"; absent before
  // 2026-11-28, -1 here: the masks are then built where the macrocells are, and a load whose
  // check stamp passed renders without them, as before).
  int64_t subcell_masks = -1;
  // reference: the entries of mesh_region_vertices.bin, each macrocell's vertex list
  // (RegionVertices; its offsets in mesh_region_first.bin), or 0 where none are stored (manifest key
  // "region_vertices"; absent before 2026-11-28 and where the lists pass their build's budget:
  // a render's ranges then pass over the elements).
  uint64_t region_vertices = 0;
  bool compact() const { return encoding == MeshEncoding::compact; }
};

struct DatasetManifest {
  int format_version = kDatasetFormatVersion;
  DatasetKind kind = DatasetKind::amr;  // manifest key "kind" (absent in older datasets: amr)
  MeshCounts mesh;                      // umesh only
  std::string source;                   // what it was converted from
  WorldTransform transform;
  box3i grid_bounds;  // bounding box of all cells, grid units
  uint64_t cell_count = 0;
  std::vector<LevelInfo> levels;
  std::vector<FieldInfo> fields;
  std::vector<double> step_times;
  uint64_t brick_count = 0, abr_count = 0, abr_brick_count = 0;
  // Nodes of the stored ABR BVH (abr_bvh.bin; manifest key "abr_bvh_node_count", absent in
  // older datasets: 0, the BVH is built at load).
  uint64_t abr_bvh_node_count = 0;
  // Chunks in the stored ABR chunk index (abr_chunks.bin; manifest key "abr_chunk_count",
  // absent in older datasets: 0, and a data-parallel rank reads every ABR).
  uint64_t abr_chunk_count = 0;
  // The dataset also holds every step in file order and file_index.bin (manifest key
  // "file_order"; absent in older datasets, which means false).
  bool file_order = false;
  int step_count() const { return int(step_times.size()); }
  // Values per (field, step) file: cells (AMR), vertices (mesh) or local vertices (compact mesh).
  uint64_t value_count() const {
    return kind == DatasetKind::amr ? cell_count : mesh.compact() ? mesh.local_vertices : mesh.vertices;
  }
  int field_index(const std::string& name) const;  // -1 if absent
};

// World cell sizes a dataset may have (the renderer works in float world coordinates).
inline constexpr double kMinCellSize = 1e-15, kMaxCellSize = 1e15;
// Empty if the transform can be rendered; else what is wrong (non-finite, non-positive or
// out-of-range cell size, origin too far from the grid). Checked by the reader and at convert.
std::string transform_problem(const WorldTransform& t);

// Names of files inside a dataset directory.
namespace dataset_files {
inline constexpr const char* kManifest = "manifest.json";
inline constexpr const char* kCells = "cells.bin";
inline constexpr const char* kBricks = "bricks.bin";
inline constexpr const char* kAbrs = "abrs.bin";
inline constexpr const char* kAbrBricks = "abr_bricks.bin";
inline constexpr const char* kAbrBvh = "abr_bvh.bin";                // per node: uint32 child or item, uint32 is_leaf
inline constexpr const char* kAbrChunks = "abr_chunks.bin";          // AbrChunk per chunk of ABRs (amr/abrs.h)
inline constexpr const char* kFileIndex = "file_index.bin";          // only with file-order copies
inline constexpr const char* kMeshVertices = "mesh_vertices.bin";    // umesh: float x, y, z per vertex
inline constexpr const char* kMeshElements = "mesh_elements.bin";    // umesh: UElement per element
inline constexpr const char* kMeshBvhNodes = "mesh_bvh_nodes.bin";   // umesh: ElementBvhNode per node
inline constexpr const char* kMeshBvhItems = "mesh_bvh_items.bin";   // umesh: uint32 per element
inline constexpr const char* kMeshNeighbors = "mesh_neighbors.bin";  // umesh: 6 uint32 per element
inline constexpr const char* kMeshTetWalk = "mesh_tet_walk.bin";     // umesh: TetWalkRecord per element
// umesh: the macrocell grid (MacroGrid), then StoredMacrocell per non-empty macrocell
inline constexpr const char* kMeshMacrocells = "mesh_macrocells.bin";
// umesh: per macrocell a uint32 mask index (0xffffffff: every subcell occupied), then SubcellMask per mask
inline constexpr const char* kMeshSubcells = "mesh_subcells.bin";
inline constexpr const char* kMeshRegionFirst = "mesh_region_first.bin";        // umesh: uint64 per macrocell, +1
inline constexpr const char* kMeshRegionVertices = "mesh_region_vertices.bin";  // umesh: uint32 per list entry
// umesh, reference: box3f of the vertices' bounds, then one per chunk of the BVH's item order
inline constexpr const char* kMeshChunks = "mesh_chunks.bin";
std::string field_values(const FieldInfo& f, int step);             // relative path
std::string field_file_order_values(const FieldInfo& f, int step);  // relative path (file-order copy)
std::string field_ranges(const FieldInfo& f, int step);             // relative path
}  // namespace dataset_files

// Writes a dataset: topology first, then values step by step (any order), manifest last.
class DatasetWriter {
 public:
  DatasetWriter(std::filesystem::path dir, DatasetManifest manifest_without_fields,
                const std::vector<std::string>& field_names);
  void write_topology(const AmrTopology& topology, const std::vector<Cell>& device_cells);
  void write_mesh(const UMesh& mesh);  // an unstructured-mesh dataset (kind umesh)
  // The same mesh in the compact encoding instead (built by the caller from `mesh`, whose
  // counts go to the manifest); values are then written per local vertex.
  void write_compact_mesh(const UMesh& mesh, const CompactMesh& compact);
  // values: cell_count floats in device order. Computes and stores the per-ABR ranges.
  void write_values(int field, int step, const std::vector<float>& values);
  // A mesh step whose stored values (per local vertex) are not those its range is taken over
  // (per vertex of the mesh: a vertex of no element counts, as in the reference encoding).
  void write_values(int field, int step, const std::vector<float>& values, Range step_range);
  // The file-order copies: `index[device position]` = position in the file-order values (a
  // permutation of 0 .. cell_count-1), written once; then per (field, step) the values in that
  // order. Writing the index marks the dataset as having file-order copies.
  void write_file_index(const std::vector<uint32_t>& index);
  void write_file_order_values(int field, int step, const float* values, uint64_t count);
  void finish();  // writes manifest.json
  const DatasetManifest& manifest() const { return manifest_; }

 private:
  std::filesystem::path dir_;
  DatasetManifest manifest_;
  const AmrTopology* topology_ = nullptr;
  void write_abr_bvh(const AmrTopology& topology);
  void write_abr_chunks(const AmrTopology& topology);
  void write_macrocells(const MacroCells& cells);
  void write_subcells(const MacroCells::SubcellMasks& subcells);  // with the macrocells
  void write_region_vertices(const std::optional<RegionVertices>& lists);
};

// One data-parallel rank's share of a dataset (mpi/partition.h): global indices, ascending.
struct DatasetPart {
  std::vector<uint32_t> bricks, abrs;  // AMR
  // Meshes (mpi/mesh_share.h): the items of the mesh index held (compact leaves, reference
  // chunks of the BVH's item order), and the whole mesh's macrocell grid, which the part is
  // rendered on.
  std::vector<uint32_t> mesh_items;
  MacroGrid mesh_grid;
  Box3<double> owned;         // the rank's region (grid units, half-open)
  Box3<double> world_bounds;  // of the whole dataset: defaults (camera, reference step) stay global
  uint64_t owned_cells = 0;   // cells in `owned` (the rest of the bricks' cells are ghosts)
};

// How much topology a Dataset reads at open. `deferred` (a data-parallel rank): a mesh that
// stores its index (umesh/mesh_index.h; datasets written since issue 17) is opened with only
// that (compact: the tree, leaf and sub-mesh records; reference: the chunk boxes; both: the
// macrocells), and restrict_to reads only the part's items (compact: leaf bytes and vertices;
// reference: BVH items, elements and vertices). AMR that stores its ABR chunk index
// (abr_chunks.bin) is opened with the bricks and that index only; read_abr_chunks then reads
// the ABRs of the chunks a rank chooses and their brick lists (the stored ABR BVH is never read:
// a part's is built over it). Any other dataset is read whole as with `whole`.
enum class TopologyLoad { whole, deferred };

// A dataset opened for reading. Topology is loaded on open (or, deferred, at restrict_to);
// values on request.
class Dataset {
 public:
  explicit Dataset(const std::filesystem::path& dir, TopologyLoad load = TopologyLoad::whole);  // throws InputError
  const DatasetManifest& manifest() const { return manifest_; }
  // AMR (empty for a mesh). Deferred: the bricks only, until read_abr_chunks adds its chunks' ABRs.
  const AmrTopology& topology() const { return topology_; }
  DatasetKind kind() const { return manifest_.kind; }
  bool is_mesh() const { return manifest_.kind == DatasetKind::umesh; }
  // The mesh's topology is still to be read (opened deferred and not yet restricted): mesh() and
  // compact_mesh() are not available (logic_error) and mesh_vertices() is empty; mesh_index() is.
  // AMR: the ABRs are still to be read (read_abr_chunks); abr_chunks() is available.
  bool topology_deferred() const { return deferred_; }
  // AMR, before restrict_to: the ABR chunk index, read at open when deferred, else made from the
  // ABRs (the same index).
  std::vector<AbrChunk> abr_chunks() const;
  // AMR opened deferred: reads the ABRs of `chunks` (ascending) and their brick lists, checked as
  // at a whole read and each ABR within its chunk's box and width (InputError otherwise). The
  // topology then holds those ABRs (abr_id gives their global indices) with every brick.
  void read_abr_chunks(const std::vector<uint32_t>& chunks);
  // The global index of topology().abrs[i] (before restrict_to).
  uint32_t abr_id(uint32_t i) const { return abr_subset_ ? abr_ids_.at(i) : i; }
  // A mesh's index (before restrict_to; logic_error otherwise): read at open when deferred, else
  // made from the mesh (the same index).
  MeshIndex mesh_index() const;
  // The world box of the mesh's vertices (also deferred: stored in the index).
  Box3<double> mesh_world_bounds() const;
  // A mesh in the reference encoding (logic_error for a compact one: it is never built at load).
  const UMesh& mesh() const;
  const MeshAccel& mesh_accel() const;  // the reference encoding's stored BVH and adjacency
  // The whole mesh's macrocells, built at a whole load on the grid convert stored (one pass over
  // the elements and a cube root per cell: 1 M tets about 22 ms on two cores, where the
  // renderer's build took a pass for the bounds and 30 ms with a cube root per element), which a
  // renderer takes instead of building them; null for a part, or a dataset stored without a grid.
  const MacroCells* macrocells() const;
  // Each of those macrocells' vertex list as convert stored it (mapped; checked against the mesh
  // as the rest), which a renderer reads its ranges from; null for a part, a compact mesh, or a
  // dataset stored without them.
  const RegionVertices* region_vertices() const;
  bool is_compact_mesh() const { return is_mesh() && manifest_.mesh.compact(); }
  const CompactMesh& compact_mesh() const;  // a mesh stored compact (logic_error otherwise)
  // The mesh's vertices in either encoding (the compact one replicates some: same bounds).
  std::span<const vec3f> mesh_vertices() const {
    if (is_compact_mesh()) return compact_.vertices;
    return mesh_.vertices;
  }
  const std::filesystem::path& dir() const { return dir_; }
  std::vector<Cell> load_cells() const;  // device order; for brute-force reference only
  // All values in device order, or with a part only those of its bricks (in its device order).
  std::vector<float> load_values(int field, int step) const;
  // Keeps only `part` of the topology. AMR: bricks renumbered in its order, their values packed
  // (value_offset into the part's arrays), ABRs and their brick lists renumbered alike. Meshes:
  // the part's leaves or the elements of its chunks with only their vertices (umesh/subset.h;
  // the reference encoding's BVH and adjacency rebuilt over them). From now on load_values and
  // load_abr_ranges read only the part's bytes. The topology files are read whole at open, but
  // for a deferred mesh, of which only the part's items are read now (checked as at open:
  // InputError). A deferred AMR part's ABRs must have been read (read_abr_chunks).
  void restrict_to(DatasetPart part);
  const DatasetPart* part() const { return restricted_ ? &part_ : nullptr; }
  uint64_t value_bytes_read() const { return value_bytes_read_; }        // by load_values, so far
  uint64_t topology_bytes_read() const { return topology_bytes_read_; }  // of topology files, so far
  // Host bytes of the topology held (the mesh in its encoding, or bricks, ABRs and their lists).
  uint64_t topology_bytes() const {
    return uint64_t(mesh_bytes_.bytes() + brick_bytes_.bytes() + abr_bytes_.bytes() + abr_list_bytes_.bytes());
  }
  std::vector<Range> load_abr_ranges(int field, int step) const;
  // Path of a field file (for the streaming reader).
  std::filesystem::path values_path(int field, int step) const;

  // File-order copies (manifest().file_order): the same values in file (source) order, and the
  // permutation from device order to it: values[i] == file_order_values[file_index[i]].
  bool has_file_order() const { return manifest_.file_order; }
  std::filesystem::path file_order_values_path(int field, int step) const;
  // Checked to be a permutation of 0 .. cell_count-1 (InputError naming the file otherwise).
  std::vector<uint32_t> load_file_index() const;
  std::vector<float> load_file_order_values(int field, int step) const;

 private:
  void load_amr(TopologyLoad load);
  void load_mesh();
  void load_compact_mesh();
  void load_compact_index();
  void load_reference_index();
  void read_reference_part(const std::vector<uint32_t>& chunks, std::vector<uint32_t>& source_vertex);
  void read_stored_macrocells();
  void read_stored_subcells();  // into stored_cells_ (datasets that store them)
  // Replaces the stored macrocells by those the mesh gives on the stored grid (InputError unless
  // the non-empty cells are the same); true when the stored step widths were the same too, so
  // that a load whose checks passed before (io/check_stamp.h) may take the stored ones as they are.
  bool build_macrocells_on_stored_grid();
  void map_stored_region_vertices();
  void check_stored_region_vertices() const;  // against the macrocells built on the stored grid
  std::vector<std::filesystem::path> mesh_files(bool with_macrocells) const;
  void read_compact_part(const std::vector<uint32_t>& leaves, std::vector<uint32_t>& source_vertex);
  // read_records and map_records, counted in topology_bytes_read.
  template <typename T>
  std::vector<T> read_topology(const std::filesystem::path& path, uint64_t count);
  template <typename T>
  HostArray<T> map_topology(const std::filesystem::path& path, uint64_t count);
  void restrict_bricks(const DatasetPart& part);
  uint32_t local_abr(uint32_t global) const;  // its position in topology_.abrs
  void read_stored_abr_chunks();
  void read_chunk_abrs(const std::vector<uint32_t>& chunks);
  void read_abr_lists();
  void check_abrs_in_chunks() const;
  void restrict_mesh(const std::vector<uint32_t>& items);
  std::filesystem::path dir_;
  DatasetManifest manifest_;
  AmrTopology topology_;
  UMesh mesh_;
  MeshAccel mesh_accel_;
  CompactMesh compact_;
  std::optional<RegionVertices> stored_region_vertices_;
  CountedBytes mesh_bytes_;
  CountedBytes brick_bytes_, abr_bytes_, abr_list_bytes_;  // the topology's host memory
  DatasetPart part_;
  bool restricted_ = false;
  std::vector<ByteRun> part_runs_;  // the part's values in a (field, step) file
  mutable std::atomic<uint64_t> value_bytes_read_{0};
  std::atomic<uint64_t> topology_bytes_read_{0};  // read_topology may run on two threads
  bool deferred_ = false;
  MacroCells stored_cells_;         // the whole mesh's, from mesh_macrocells.bin (when stored)
  std::vector<box3f> chunk_boxes_;  // deferred reference encoding: from mesh_chunks.bin
  box3f vertex_bounds_;
  std::vector<AbrChunk> stored_abr_chunks_;  // deferred AMR: from abr_chunks.bin
  std::vector<uint32_t> abr_ids_;            // after read_abr_chunks: global index of each ABR held
  bool abr_subset_ = false;                  // topology_.abrs are abr_ids_ (read_abr_chunks)
  // The stored ABR BVH's tree (boxes unset), checked (InputError); its bytes not counted (it is
  // read beside the ABRs, whose reads count theirs).
  std::vector<BvhNode> read_abr_bvh_tree() const;
  void count_topology_bytes();
  void count_mesh_bytes();
};

// Converts any source into a dataset directory, reading one (field, step) at a time.
struct ConvertOptions {
  bool quiet = false;               // no progress bar
  bool file_order = false;          // also write every step in file (source) order + file_index.bin
  std::vector<std::string> fields;  // the source's fields to keep (empty: all); InputError for an unknown name
  // Meshes: the encoding stored (reference or compact; `stored` means reference). The CLI's
  // default is compact.
  MeshEncoding mesh_encoding = MeshEncoding::reference;
  // Meshes: pyramids, wedges and hexahedra stored as tets (umesh/split_tets.h).
  bool split_into_tets = false;
  static ConvertOptions silent() {  // everything, no progress bar
    ConvertOptions o;
    o.quiet = true;
    return o;
  }
};
struct ConvertStats {
  double cells_seconds = 0, bricks_seconds = 0, abrs_seconds = 0, values_seconds = 0;
  uint64_t topology_bytes = 0;  // bricks + ABRs + ABR brick lists
};
// InputError (naming `out`) unless about cells * (topology + values_per_cell floats) bytes fit on
// the file system that will hold `out`: a demo or convert must not fill the disk and fail late.
void check_free_space(const std::filesystem::path& out, uint64_t cells, uint64_t values_per_cell, bool file_order);
// The values of one (field, step) as a dataset stores them: NaN is "no data" (kept), an
// infinite value (also a float64 beyond float range, converted) is refused (InputError naming
// `origin`), and some value must be finite so that the step has a range (docs/formats.md).
void check_field_values(const std::vector<float>& values, const std::string& origin, const std::string& field,
                        int step);
ConvertStats convert_to_dataset(AmrSource& source, const std::filesystem::path& out_dir,
                                const ConvertOptions& options = {});

}  // namespace vs
