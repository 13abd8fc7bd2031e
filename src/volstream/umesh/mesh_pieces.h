// Pieces of one mesh as parallel writers leave them (the <Piece>s of a .vtu, the files of a
// .pvtu, the parts of a .pvd time step), joined into one MeshData.
#pragma once
#include <string>
#include <vector>

#include "volstream/umesh/mesh_data.h"

namespace vs {

// VTK's ghost flags (vtkDataSetAttributes): a cell another piece owns, or one hidden from view.
constexpr uint8_t kGhostDuplicateCell = 1, kGhostHiddenCell = 32;

// The pieces in order as one mesh (point indices offset by the points before them), then:
// - cells flagged kGhostDuplicateCell or kGhostHiddenCell in a cell array "vtkGhostType" are
//   dropped (their owner has them), and the "vtkGhostType" arrays of points and cells with them
//   (they describe the split, not the data);
// - with two pieces or more, points the pieces share are made one: those at the same coordinates
//   with the same point data, bit for bit. Welded, a ray's walk crosses the seams through face
//   neighbours as it does inside a piece, instead of searching the element BVH at each seam.
//   Points at one place with different values (a discontinuity the writer meant) stay apart;
// - points no cell uses any more (a ghost cell's) are dropped.
// Empty pieces (no points, no cells: a rank that had none) are skipped. One piece without ghost
// cells comes back as it is, but for its vtkGhostType arrays. With `missing` refused, every piece
// must carry the same point and cell arrays (names and components, in order), as the pieces of
// one parallel writer's step do: InputError naming `origin` otherwise. With `missing` no_data
// (the parts of a model, as a multiblock's blocks or a CGNS file's zones: a solid without a
// fluid's velocity), an array some piece lacks is NaN, no data, on that piece's points or cells;
// an array with other components in another piece is still refused.
enum class MissingArrays { refused, no_data };

// Drops the points no cell of `m` uses, with their point data, keeping the others' order;
// returns which of the old points are kept.
std::vector<bool> drop_unused_points(MeshData& m);
MeshData join_pieces(std::vector<MeshData> pieces, const std::string& origin,
                     MissingArrays missing = MissingArrays::refused);

// The inverse, as a parallel run would write the mesh: `count` pieces of consecutive cells, each
// with its own copy of the points it uses (in first-use order) and their data; with `ghosts` > 0,
// each piece also holds up to that many of the cells after its own, flagged kGhostDuplicateCell
// in a cell array "vtkGhostType" (with a point array "vtkGhostType" of zeros, as VTK writes).
// For tests and `volstream demo --write-mesh NAME.pvtu`.
std::vector<MeshData> cut_into_pieces(const MeshData& mesh, int count, uint64_t ghosts = 0);

}  // namespace vs
