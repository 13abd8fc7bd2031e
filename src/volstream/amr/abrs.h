// Active brick region builder: partitions the union of brick supports into disjoint boxes, each
// with the list of bricks whose support overlaps it.
#pragma once
#include <string>
#include <vector>

#include "volstream/amr/model.h"
#include "volstream/core/chunks.h"

namespace vs {

// Fills topology.abrs and topology.abr_bricks from topology.bricks. Throws InputError(source_name)
// when two bricks overlap (cells given twice at different levels).
void build_abrs(AmrTopology& topology, const std::string& source_name);

// The ABRs' boxes, in ABR order.
std::vector<box3f> abr_boxes(const AmrTopology& topology);

// The BVH over the ABR boxes with its boxes set: a copy of topology.abr_bvh when the dataset
// stores it (checked and refit at load), else a binned SAH build (a quarter of a whole `render`
// of the 486k-ABR jet, hence stored at convert).
Bvh build_abr_bvh(const AmrTopology& topology);

// What a data-parallel rank chooses ABRs by without reading them (mpi/amr_share.h): per chunk of
// kIndexChunk consecutive ABRs (core/chunks.h; the builder emits them subtree by subtree, so a
// chunk is compact) the box holding them and the largest of their finest widths (the margin
// rule's widths grow with it). Stored at convert (abr_chunks.bin, docs/formats.md).
struct AbrChunk {
  box3f box;
  float finest_width;
};
static_assert(sizeof(AbrChunk) == 28);
std::vector<AbrChunk> abr_chunks(const std::vector<Abr>& abrs);

}  // namespace vs
