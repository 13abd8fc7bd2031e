// Parts of a mesh (a data-parallel rank's share, mpi/mesh_share.h): the elements, or compact
// leaves, asked for and only the vertices they use, renumbered in ascending order of the whole
// mesh's, so that a field's values for the part are runs of the whole field file.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/umesh/compact.h"
#include "volstream/umesh/umesh.h"

namespace vs {

// `elements`: ascending indices into mesh.elements. source_vertex[i]: the whole mesh's vertex of
// the part's vertex i (ascending).
UMesh mesh_subset(const UMesh& mesh, const std::vector<uint32_t>& elements, std::vector<uint32_t>& source_vertex);
// mesh_subset for a reader that has only the asked-for element records (checked: their slots
// and indices valid): the part without vertex positions (the caller sets the positions of
// source_vertex, in order).
UMesh mesh_part(std::vector<UElement> elements, std::vector<uint32_t>& source_vertex);

// `leaves`: ascending indices into mesh.leaves. The leaves keep their order, elements and corner
// bytes; their vertex tables are renumbered into the part's sub-meshes (those of the whole mesh
// that hold a leaf, each with only the vertices its leaves use) and the tree is rebuilt over
// them. source_vertex[i]: the whole mesh's local vertex of the part's local vertex i (ascending).
CompactMesh compact_subset(const CompactMesh& mesh, const std::vector<uint32_t>& leaves,
                           std::vector<uint32_t>& source_vertex);

// compact_subset in two steps, for a reader that has only the asked-for leaves (Dataset reading
// a rank's share): from their records (in the whole mesh's order, sub-meshes the whole mesh's)
// and bytes (checked: compact_store.h), the part without vertex positions, and source_vertex;
// then its vertices (the positions of source_vertex, in order) and its tree. The part's leaf
// boxes are returned.
struct CompactPieces {
  std::vector<CompactLeaf> leaves;
  std::vector<const uint8_t*> bytes;  // each leaf's vertex table and corners
};
CompactMesh compact_part(const CompactPieces& pieces, const HostArray<CompactSubmesh>& submeshes,
                         std::vector<uint32_t>& source_vertex);
std::vector<box3f> finish_compact_part(CompactMesh& part, std::vector<vec3f> vertices);

}  // namespace vs
