// What a data-parallel rank chooses its share of a mesh by (mpi/mesh_share.h), without the
// mesh's elements or vertices, so that it reads only the items it holds (Dataset, opened with
// its topology deferred): items of a few dozen elements close together, per item a box that
// holds its elements and their count, and the whole mesh's macrocells (grid, boxes and step
// widths: what held_regions selects by, and the grid a part is rendered on).
//   - compact encoding: the items are the leaves; their boxes are the leaves' parents' quantized
//     child boxes (compact_nodes.bin: 10 B a leaf; rounded outwards, a little larger);
//   - reference encoding: the items are chunks of kReferenceChunk consecutive elements of the
//     element BVH's item order (mesh_bvh_items.bin: leaf after leaf, so a chunk is compact),
//     their exact boxes stored at convert (mesh_chunks.bin, after the vertices' bounds).
// The macrocells are stored at convert (mesh_macrocells.bin, docs/formats.md) as one process
// builds them at load.
#pragma once
#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "volstream/core/chunks.h"
#include "volstream/umesh/compact.h"
#include "volstream/umesh/macrocells.h"
#include "volstream/umesh/umesh.h"

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

// The reference encoding's items: chunks (core/chunks.h) of the element BVH's item order.
inline constexpr uint32_t kReferenceChunk = kIndexChunk;

struct MeshIndex {
  std::vector<box3f> item_boxes;        // each holds its item's elements
  std::vector<uint32_t> item_elements;  // elements per item
  MacroCells cells;                     // the whole mesh's
  // Where the partition counts each item's elements: its box's centre (grid units).
  std::vector<vec3d> item_points() const;
};
// From a compact mesh's tree and leaf records (checked: check_compact_tree; bytes and vertices
// unused) and its macrocells.
MeshIndex compact_mesh_index(const CompactMesh& mesh, MacroCells cells);
// The reference encoding's chunk boxes (of `bvh_items`, the element BVH's item order).
std::vector<box3f> reference_chunk_boxes(const UMesh& mesh, std::span<const uint32_t> bvh_items);
// From the chunk boxes of a mesh of `elements` elements and its macrocells.
MeshIndex reference_mesh_index(std::vector<box3f> chunk_boxes, uint64_t elements, MacroCells cells);
// The elements of the chunks (ascending) of the BVH's item order, ascending.
std::vector<uint32_t> chunk_elements(const std::vector<uint32_t>& chunks, std::span<const uint32_t> bvh_items);

}  // namespace vs
