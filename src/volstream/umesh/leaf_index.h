// What a data-parallel rank chooses its share of a compact mesh by (mpi/mesh_share.h), without
// the mesh's bytes or vertices, so that it reads only the leaves it holds (Dataset, opened with
// its topology deferred): per leaf a box that holds it and its element count, and the whole
// mesh's macrocells (grid, boxes and step widths: what held_regions selects by, and the grid a
// part is rendered on). The boxes are the leaves' parents' quantized child boxes
// (compact_nodes.bin: 10 B a leaf; rounded outwards, so a little larger than the leaves). The
// macrocells are stored at convert (mesh_macrocells.bin, docs/formats.md) as one process builds
// them at load.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "volstream/umesh/compact.h"
#include "volstream/umesh/macrocells.h"

namespace vs {

// A non-empty macrocell as stored: its grid cell and step width (region order: cells ascending).
struct StoredMacrocell {
  uint32_t cell;
  float step_width;
};
static_assert(sizeof(StoredMacrocell) == 8);
static_assert(sizeof(MacroGrid) == 48);

std::vector<StoredMacrocell> stored_macrocells(const MacroCells& cells);
// The macrocells back (boxes from the grid, as build_macrocells makes them). InputError naming
// `file` unless the grid is build_macrocells' grid for its bounds and `elements` elements, and
// the cells ascend strictly inside it with finite, non-negative step widths.
MacroCells macrocells_from_stored(const MacroGrid& grid, const std::vector<StoredMacrocell>& stored, uint64_t elements,
                                  const std::string& file);

struct CompactLeafIndex {
  std::vector<box3f> leaf_boxes;        // each holds its leaf's elements
  std::vector<uint32_t> leaf_elements;  // elements per leaf
  MacroCells cells;                     // the whole mesh's
  // Where the partition counts each leaf's elements: its box's centre (grid units).
  std::vector<vec3d> leaf_points() const;
};
// From a mesh's tree and leaf records (checked: check_compact_tree; bytes and vertices unused)
// and its macrocells.
CompactLeafIndex compact_leaf_index(const CompactMesh& mesh, MacroCells cells);

}  // namespace vs
