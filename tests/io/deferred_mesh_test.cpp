// A mesh opened with its topology deferred (issue 17: a data-parallel rank reads only its items),
// in both encodings: at open only the mesh index is read (compact: tree, leaf and sub-mesh
// records; reference: chunk boxes; both: the stored macrocells), which equals the index made from
// the whole mesh; a part read from the files equals the part made from the whole mesh, array for
// array, with the same values, for less than the whole topology; damaged files are refused with
// one line naming the file, at open or at the part read.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <regex>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/mpi/mesh_share.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

fs::path convert_holes(MeshEncoding encoding) {
  const fs::path d =
      test::scratch_dir(encoding == MeshEncoding::compact ? "deferred_holes_compact" : "deferred_holes_reference");
  auto series = make_mesh_demo_series({"holes", 6000, 1});
  ConvertOptions options = ConvertOptions::silent();
  options.mesh_encoding = encoding;
  convert_mesh_to_dataset(*series, d, options);
  return d;
}
const fs::path& holes_dir(MeshEncoding encoding = MeshEncoding::compact) {
  static const fs::path compact = convert_holes(MeshEncoding::compact);
  static const fs::path reference = convert_holes(MeshEncoding::reference);
  return encoding == MeshEncoding::compact ? compact : reference;
}
constexpr MeshEncoding kEncodings[] = {MeshEncoding::compact, MeshEncoding::reference};

uint64_t topology_file_bytes(const fs::path& dir) {
  uint64_t bytes = 0;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".bin") bytes += entry.file_size();
  return bytes;
}

// Rank `rank` of `ranks`'s leaves, chosen as ParallelRenderer chooses them.
std::vector<uint32_t> share_of(const MeshIndex& index, int rank, int ranks) {
  const std::vector<vec3d> points = index.item_points();
  const Partition p = partition_points(points, ranks, index.item_elements);
  return mesh_share(index, points, p.regions[size_t(rank)], IntegratorSettings{}).items;
}

template <typename Array>
void expect_same_bytes(const Array& a, const Array& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(typename Array::value_type)), 0) << what;
}

void expect_index_only_at_open(const fs::path& dir) {
  const Dataset whole(dir), deferred(dir, TopologyLoad::deferred);
  EXPECT_FALSE(whole.topology_deferred());
  EXPECT_TRUE(deferred.topology_deferred());
  const uint64_t files = topology_file_bytes(dir);
  EXPECT_LT(deferred.topology_bytes_read(), files / 3) << "of " << files;
  EXPECT_THROW(deferred.is_compact_mesh() ? (void)deferred.compact_mesh() : (void)deferred.mesh(), std::logic_error);
  const Box3<double> a = whole.mesh_world_bounds(), b = deferred.mesh_world_bounds();
  EXPECT_EQ(a.lower, b.lower);
  EXPECT_EQ(a.upper, b.upper);
  const MeshIndex built = whole.mesh_index(), stored = deferred.mesh_index();
  EXPECT_EQ(built.cells.grid.dims, stored.cells.grid.dims);
  EXPECT_EQ(built.cells.grid.bounds.lower, stored.cells.grid.bounds.lower);
  EXPECT_EQ(built.cells.grid.bounds.upper, stored.cells.grid.bounds.upper);
  EXPECT_EQ(built.cells.region_of_cell, stored.cells.region_of_cell);
  EXPECT_EQ(built.cells.step_width, stored.cells.step_width);
  EXPECT_EQ(built.cells.cell_of_region, stored.cells.cell_of_region);
  expect_same_bytes(built.item_boxes, stored.item_boxes, "leaf boxes");
  EXPECT_EQ(built.item_elements, stored.item_elements);
}

TEST(DeferredMesh, OpensWithTheIndexOnlyWhichIsTheOneMadeFromTheMesh) {
  for (const MeshEncoding encoding : kEncodings) {
    SCOPED_TRACE(encoding == MeshEncoding::compact ? "compact" : "reference");
    expect_index_only_at_open(holes_dir(encoding));
  }
}

void expect_same_parts(const Dataset& whole, const Dataset& deferred) {
  if (whole.is_compact_mesh()) {
    const CompactMesh &a = whole.compact_mesh(), &b = deferred.compact_mesh();
    expect_same_bytes(a.nodes, b.nodes, "nodes");
    expect_same_bytes(a.leaves, b.leaves, "leaves");
    expect_same_bytes(a.bytes, b.bytes, "bytes");
    expect_same_bytes(a.submeshes, b.submeshes, "sub-meshes");
    expect_same_bytes(a.vertices, b.vertices, "vertices");
    EXPECT_EQ(a.leaf_parents, b.leaf_parents);
    return;
  }
  expect_same_bytes(whole.mesh().vertices, deferred.mesh().vertices, "vertices");
  expect_same_bytes(whole.mesh().elements, deferred.mesh().elements, "elements");
  expect_same_bytes(whole.mesh_accel().bvh.nodes, deferred.mesh_accel().bvh.nodes, "BVH nodes");
  EXPECT_EQ(whole.mesh_accel().neighbors, deferred.mesh_accel().neighbors);
}

void expect_parts_equal(const fs::path& dir) {
  const uint64_t files = topology_file_bytes(dir);
  const int ranks = 4;
  uint64_t read = 0;
  for (int rank = 0; rank < ranks; ++rank) {
    Dataset whole(dir), deferred(dir, TopologyLoad::deferred);
    const std::vector<uint32_t> items = share_of(deferred.mesh_index(), rank, ranks);
    ASSERT_EQ(items, share_of(whole.mesh_index(), rank, ranks));
    const size_t item_count = whole.mesh_index().item_boxes.size();
    DatasetPart part;
    part.mesh_items = items;
    whole.restrict_to(part);
    deferred.restrict_to(part);
    EXPECT_FALSE(deferred.topology_deferred());
    expect_same_parts(whole, deferred);
    EXPECT_EQ(whole.load_values(0, 0), deferred.load_values(0, 0));
    EXPECT_LT(deferred.topology_bytes_read(), files) << "rank " << rank;
    read += deferred.topology_bytes_read();
    std::printf("rank %d of %d: %zu of %zu items, topology read %llu of %llu B\n", rank, ranks, items.size(),
                item_count, (unsigned long long)deferred.topology_bytes_read(), (unsigned long long)files);
  }
  EXPECT_LT(read, uint64_t(ranks) * files);
}

TEST(DeferredMesh, PartReadFromTheFilesEqualsThePartOfTheWholeMesh) {
  for (const MeshEncoding encoding : kEncodings) {
    SCOPED_TRACE(encoding == MeshEncoding::compact ? "compact" : "reference");
    expect_parts_equal(holes_dir(encoding));
  }
}

// A whole load hands the renderer the macrocells convert stored, which are the ones it would
// build from the mesh; a part builds its own (on the whole grid), so it gets none.
TEST(DeferredMesh, WholeLoadOffersTheStoredMacrocellsWhichAreTheBuiltOnes) {
  for (const MeshEncoding encoding : kEncodings) {
    SCOPED_TRACE(encoding == MeshEncoding::compact ? "compact" : "reference");
    Dataset whole(holes_dir(encoding));
    const MacroCells* stored = whole.macrocells();
    ASSERT_NE(stored, nullptr);
    const MacroCells built =
        whole.is_compact_mesh() ? build_macrocells(whole.compact_mesh()) : build_macrocells(whole.mesh());
    EXPECT_EQ(stored->grid.dims, built.grid.dims);
    EXPECT_EQ(stored->grid.cell_size, built.grid.cell_size);
    EXPECT_EQ(stored->grid.bounds.lower, built.grid.bounds.lower);
    EXPECT_EQ(stored->grid.bounds.upper, built.grid.bounds.upper);
    EXPECT_EQ(stored->region_of_cell, built.region_of_cell);
    EXPECT_EQ(stored->cell_of_region, built.cell_of_region);
    EXPECT_EQ(stored->step_width, built.step_width);
    DatasetPart part;
    part.mesh_items = {0, 1};
    whole.restrict_to(part);
    EXPECT_EQ(whole.macrocells(), nullptr);
  }
}

// A dataset written before the mesh index (no macrocell count, no index files, and so no
// macrocell vertex lists) is read whole, deferred or not, and gives the same index and parts.
TEST(DeferredMesh, DatasetsWithoutAnIndexAreReadWhole) {
  for (const MeshEncoding encoding : kEncodings) {
    const bool compact = encoding == MeshEncoding::compact;
    const fs::path dir = test::damaged_copy(
        holes_dir(encoding), compact ? "old_compact" : "old_reference", "manifest.json", [](std::vector<char>& b) {
          const std::string text(b.begin(), b.end());
          const std::string old = std::regex_replace(text, std::regex("\"(macrocells|region_vertices)\": \\d+,"), "");
          b.assign(old.begin(), old.end());
        });
    fs::remove(dir / "mesh_macrocells.bin");
    fs::remove(dir / "mesh_chunks.bin");
    for (const char* lists : {"mesh_region_first.bin", "mesh_region_vertices.bin"}) fs::remove(dir / lists);
    Dataset old(dir, TopologyLoad::deferred), indexed(holes_dir(encoding), TopologyLoad::deferred);
    EXPECT_FALSE(old.topology_deferred());
    EXPECT_EQ(old.manifest().mesh.macrocells, 0u);
    const std::vector<uint32_t> items = share_of(indexed.mesh_index(), 1, 3);
    ASSERT_EQ(items, share_of(old.mesh_index(), 1, 3));
    DatasetPart part;
    part.mesh_items = items;
    old.restrict_to(part);
    indexed.restrict_to(part);
    expect_same_parts(old, indexed);
  }
}

// The line a deferred open and a read of leaves 0 .. 7 give for a damaged copy ("accepted" if none).
std::string read_damaged(const std::string& name, const std::string& file,
                         const std::function<void(std::vector<char>&)>& damage,
                         MeshEncoding encoding = MeshEncoding::compact) {
  const fs::path dir = test::damaged_copy(holes_dir(encoding), "deferred_damaged_" + name, file, damage);
  return test::input_error_line([&] {
    Dataset ds(dir, TopologyLoad::deferred);
    DatasetPart part;
    for (uint32_t l = 0; l < 8; ++l) part.mesh_items.push_back(l);
    ds.restrict_to(part);
  });
}

template <typename T>
void patch(std::vector<char>& bytes, size_t at, T value) {
  std::memcpy(bytes.data() + at, &value, sizeof(T));
}

// A whole load takes only the grid from mesh_macrocells.bin and builds the cells on it, so a
// grid that does not bound the mesh, or cells that are not its non-empty ones, are refused;
// step widths are the mesh's own (a damaged width changes nothing).
TEST(DeferredMesh, WholeLoadRefusesStoredMacrocellsThatAreNotTheMeshs) {
  for (const MeshEncoding encoding : kEncodings) {
    SCOPED_TRACE(encoding == MeshEncoding::compact ? "compact" : "reference");
    const std::string name = encoding == MeshEncoding::compact ? "whole_cells_compact_" : "whole_cells_reference_";
    auto whole_load = [&](const std::string& what, const std::function<void(std::vector<char>&)>& damage) {
      const fs::path dir = test::damaged_copy(holes_dir(encoding), name + what, "mesh_macrocells.bin", damage);
      return test::input_error_line([&] { Dataset ds(dir); });
    };
    // The grid's lower x moved out a little: still a grid of the same dims and cell size
    // (bounds are checked to give them), but not this mesh's bounds.
    const Dataset whole(holes_dir(encoding));
    const MacroGrid grid = whole.macrocells()->grid;
    const float widened = std::nextafter(grid.bounds.lower.x, -INFINITY);
    std::string line = whole_load("bounds", [&](auto& b) { patch<float>(b, offsetof(MacroGrid, bounds), widened); });
    EXPECT_NE(line.find("mesh_macrocells.bin"), std::string::npos) << line;
    EXPECT_NE(line, "accepted");
    const size_t cell_count = whole.macrocells()->cell_of_region.size();
    line = whole_load("cells", [&](auto& b) {  // the last non-empty cell moved to the grid's last cell
      patch<uint32_t>(b, sizeof(MacroGrid) + 8 * (cell_count - 1), uint32_t(grid.cell_count() - 1));
    });
    if (whole.macrocells()->cell_of_region.back() != grid.cell_count() - 1) {
      EXPECT_NE(line.find("not the mesh's"), std::string::npos) << line;
    }
    {  // mesh_subcells.bin: a subcell some element's box overlaps cleared; a mask index out of
       // range; the file truncated
      const size_t index_bytes = whole.macrocells()->region_count() * sizeof(uint32_t);
      ASSERT_FALSE(whole.macrocells()->subcells.masks.empty()) << "the holes demo has empty subcells";
      const auto load_damaged = [&](const std::string& what, const std::function<void(std::vector<char>&)>& damage) {
        return test::input_error_line(
            [&] { Dataset ds(test::damaged_copy(holes_dir(encoding), name + what, "mesh_subcells.bin", damage)); });
      };
      line = load_damaged("subcell_cleared", [&](auto& b) {
        for (size_t i = index_bytes; i < b.size(); ++i)
          if (b[i] != 0) {
            b[i] = 0;
            return;
          }
      });
      EXPECT_NE(line.find("mesh_subcells.bin"), std::string::npos) << line;
      EXPECT_NE(line.find("subcell masks are not the mesh's"), std::string::npos) << line;
      line = load_damaged("subcell_index", [&](auto& b) { patch<uint32_t>(b, 0, 1u << 30); });
      EXPECT_NE(line.find("subcell masks are not the mesh's"), std::string::npos) << line;
      line = load_damaged("subcells_truncated", [](auto& b) { b.resize(b.size() - 8); });
      EXPECT_NE(line.find("mesh_subcells.bin"), std::string::npos) << line;
      EXPECT_EQ(whole.macrocells()->subcells.of_region.size(), whole.macrocells()->region_count());
    }
    const fs::path width = test::damaged_copy(holes_dir(encoding), name + "width", "mesh_macrocells.bin",
                                              [](auto& b) { patch<float>(b, sizeof(MacroGrid) + 4, 0.f); });
    const Dataset damaged(width);
    EXPECT_EQ(damaged.macrocells()->step_width, whole.macrocells()->step_width);
  }
}

TEST(DeferredMesh, ReaderRefusesDamagedFilesNamingThem) {
  auto has = [](const std::string& line, const char* file, const char* what) {
    return line.find(file) != std::string::npos && line.find(what) != std::string::npos;
  };
  const char* cells = "mesh_macrocells.bin";
  std::string line = read_damaged("cells_truncated", cells, [](auto& b) { b.resize(b.size() - 3); });
  EXPECT_TRUE(has(line, cells, "")) << line;
  EXPECT_NE(line, "accepted");
  line = read_damaged("grid", cells, [](auto& b) { patch<int32_t>(b, offsetof(MacroGrid, dims), 300); });
  EXPECT_TRUE(has(line, cells, "grid")) << line;
  line = read_damaged("bounds", cells, [](auto& b) { patch<float>(b, offsetof(MacroGrid, bounds), NAN); });
  EXPECT_TRUE(has(line, cells, "bounds")) << line;
  line = read_damaged("order", cells, [](auto& b) { patch<uint32_t>(b, sizeof(MacroGrid) + 8, 0); });
  EXPECT_TRUE(has(line, cells, "out of order")) << line;
  line = read_damaged("width", cells, [](auto& b) { patch<float>(b, sizeof(MacroGrid) + 4, -1.f); });
  EXPECT_TRUE(has(line, cells, "step width")) << line;
  // The part's leaves (0 .. 7): leaf 0's bytes start the file, its vertex table first.
  line = read_damaged("table", "compact_bytes.bin", [](auto& b) { patch<uint16_t>(b, 0, 65535); });
  EXPECT_TRUE(has(line, "compact_bytes.bin", "outside its sub-mesh")) << line;
  line = read_damaged("leaf_run", "compact_leaves.bin",
                      [](auto& b) { patch<uint32_t>(b, 12 * 5 + offsetof(CompactLeaf, first_byte), 0xfffff000u); });
  EXPECT_TRUE(has(line, "compact_leaves.bin", "beyond its sub-mesh")) << line;
  line = read_damaged("bytes_truncated", "compact_bytes.bin", [](auto& b) { b.resize(b.size() - 1); });
  EXPECT_TRUE(has(line, "compact_bytes.bin", "")) << line;
  EXPECT_NE(line, "accepted");
  // Leaf 0's first vertex moved far away: outside the box the leaf was chosen by; not finite.
  const uint16_t first = [] {
    const Dataset ds(holes_dir());
    return CompactMeshView(view_of(ds.compact_mesh())).table_entry(ds.compact_mesh().leaves[0], 0);
  }();
  line = read_damaged("moved", "compact_vertices.bin", [&](auto& b) { patch<float>(b, 12 * size_t(first), 1e30f); });
  EXPECT_TRUE(has(line, "compact_nodes.bin", "outside its box")) << line;
  line = read_damaged("nan", "compact_vertices.bin", [&](auto& b) { patch<float>(b, 12 * size_t(first), NAN); });
  EXPECT_TRUE(has(line, "compact_vertices.bin", "not finite")) << line;  // before any box is made of it
  line =
      read_damaged("cycle", "compact_nodes.bin", [](auto& b) { patch<uint32_t>(b, offsetof(CompactNode, first), 0); });
  EXPECT_TRUE(has(line, "compact_nodes.bin", "node 0")) << line;
}

TEST(DeferredMesh, ReaderRefusesDamagedReferenceFilesNamingThem) {
  auto has = [](const std::string& line, const char* file, const char* what) {
    return line.find(file) != std::string::npos && line.find(what) != std::string::npos;
  };
  const MeshEncoding ref = MeshEncoding::reference;
  const char* chunks = "mesh_chunks.bin";
  std::string line = read_damaged(
      "chunks_truncated", chunks, [](auto& b) { b.resize(b.size() - 24); }, ref);
  EXPECT_TRUE(has(line, chunks, "")) << line;
  EXPECT_NE(line, "accepted");
  line = read_damaged(
      "vertex_bounds", chunks, [](auto& b) { patch<float>(b, 0, NAN); }, ref);
  EXPECT_TRUE(has(line, chunks, "bounds")) << line;
  line = read_damaged(
      "chunk_box", chunks, [](auto& b) { patch<float>(b, 24 + 12, -1e30f); }, ref);
  EXPECT_TRUE(has(line, chunks, "chunk 0")) << line;
  // Chunk 0 (items 0 .. 31) is read: an item repeated, one out of range, an element's slot.
  const char* items = "mesh_bvh_items.bin";
  line = read_damaged(
      "repeated", items, [](auto& b) { std::memcpy(b.data() + 4, b.data(), 4); }, ref);
  EXPECT_TRUE(has(line, items, "permutation")) << line;
  line = read_damaged(
      "item_range", items, [](auto& b) { patch<uint32_t>(b, 0, 0x7fffffffu); }, ref);
  EXPECT_TRUE(has(line, items, "permutation")) << line;
  const Dataset whole(holes_dir(ref));
  const uint32_t first = whole.mesh_accel().bvh.items[0], vertex = whole.mesh().elements[first].v[0];
  line = read_damaged(
      "slot", "mesh_elements.bin", [&](auto& b) { patch<uint32_t>(b, 32 * size_t(first), 0x7ffffff0u); }, ref);
  EXPECT_TRUE(has(line, "mesh_elements.bin", "invalid")) << line;
  line = read_damaged(
      "moved", "mesh_vertices.bin", [&](auto& b) { patch<float>(b, 12 * size_t(vertex), 1e30f); }, ref);
  EXPECT_TRUE(has(line, chunks, "outside its chunk's box")) << line;
  line = read_damaged(
      "nan", "mesh_vertices.bin", [&](auto& b) { patch<float>(b, 12 * size_t(vertex), NAN); }, ref);
  EXPECT_TRUE(has(line, "mesh_vertices.bin", "not finite")) << line;
  line = read_damaged(
      "cells", "mesh_macrocells.bin", [](auto& b) { b.resize(b.size() - 8); }, ref);
  EXPECT_TRUE(has(line, "mesh_macrocells.bin", "")) << line;
  EXPECT_NE(line, "accepted");
}

}  // namespace
}  // namespace vs
