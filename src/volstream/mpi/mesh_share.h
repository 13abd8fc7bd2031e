// One data-parallel rank's share of an unstructured mesh (issue 17; mpi/partition.h). The ranks
// split the elements by their centroids (partition_points), or in the compact encoding the
// leaves by their index's points weighted by their elements (umesh/leaf_index.h: chosen without
// the mesh, so that a rank reads only its leaves). A rank samples the mesh's regions,
// its macrocells, as one process would wherever its composited light depends on them: those
// within the integrator's margin of its box (held_regions, as ABRs for AMR). A macrocell's step
// width and value range come from every element overlapping it, and a sample in it may land in
// any of them, so the rank holds all those elements (in the compact encoding: the leaves holding
// one; chosen by the leaves' index boxes, which hold them: a few more than the leaves whose
// elements overlap a held macrocell); the ones whose centroid (leaf point) lies outside its box
// are its ghosts.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/mpi/partition.h"
#include "volstream/umesh/leaf_index.h"
#include "volstream/umesh/macrocells.h"
#include "volstream/umesh/umesh.h"

namespace vs {

struct MeshShare {
  std::vector<uint32_t> items;  // elements (reference encoding) or leaves (compact), ascending
  uint64_t owned_elements = 0;  // elements whose centroid (compact: leaf point) lies in the region
  uint64_t held_elements = 0;   // elements of the items (owned + ghosts)
  double margin = 0;            // grid units (RankShare::margin)
};

// `cells`: the whole mesh's macrocells (build_macrocells); `centroids`: element_centroids.
MeshShare mesh_share(const UMesh& mesh, const MacroCells& cells, const std::vector<vec3d>& centroids,
                     const Box3<double>& region, const IntegratorSettings& settings);
// `leaf_points`: index.leaf_points().
MeshShare mesh_share(const CompactLeafIndex& index, const std::vector<vec3d>& leaf_points, const Box3<double>& region,
                     const IntegratorSettings& settings);

}  // namespace vs
