// One data-parallel rank's share of an unstructured mesh (issue 17; mpi/partition.h), chosen from
// the mesh's index (umesh/mesh_index.h: items of a few dozen elements, compact leaves or chunks
// of the element BVH's order, with boxes that hold them), so that a rank reads only its items.
// The ranks split the items by their points weighted by their elements (partition_points). A
// rank samples the mesh's regions, its macrocells, as one process would wherever its composited
// light depends on them: those within the integrator's margin of its box (held_regions, as ABRs
// for AMR). A macrocell's step width and value range come from every element overlapping it, and
// a sample in it may land in any of them, so the rank holds all those elements: every item whose
// box overlaps a held macrocell (a few more than the items whose elements do); the elements of
// items whose point lies outside its box are its ghosts.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/mpi/partition.h"
#include "volstream/umesh/mesh_index.h"

namespace vs {

struct MeshShare {
  std::vector<uint32_t> items;  // of the index, ascending
  uint64_t owned_elements = 0;  // elements of the items whose point lies in the region
  uint64_t held_elements = 0;   // elements of the items (owned + ghosts)
  double margin = 0;            // grid units (RankShare::margin)
};

// `item_points`: index.item_points().
MeshShare mesh_share(const MeshIndex& index, const std::vector<vec3d>& item_points, const Box3<double>& region,
                     const IntegratorSettings& settings);

}  // namespace vs
