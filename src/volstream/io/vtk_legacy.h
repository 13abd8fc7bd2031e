// Legacy VTK files (.vtk), DATASET UNSTRUCTURED_GRID, ASCII or BINARY (big endian), in both
// layouts of the CELLS section:
//   version < 5 (e.g. 4.2): CELLS n size, then per cell "count i0 i1 ..." (size ints in all);
//   version >= 5 (5.1):     CELLS n_offsets n_connectivity, then OFFSETS <type> and
//                           CONNECTIVITY <type> arrays (vtktypeint64 as VTK writes them).
// Read: POINTS (float or double), CELLS, CELL_TYPES, and in POINT_DATA / CELL_DATA the arrays of
// SCALARS (optional component count, optional LOOKUP_TABLE line), VECTORS, NORMALS, TENSORS and
// FIELD. METADATA blocks and dataset-level FIELD data are skipped. Anything else is an InputError.
#pragma once
#include <filesystem>

#include "volstream/umesh/mesh_data.h"

namespace vs {

MeshData read_vtk_legacy(const std::filesystem::path& file);

struct VtkLegacyWriteOptions {
  bool binary = true;
  bool version51 = true;  // 5.1 (OFFSETS/CONNECTIVITY) or 4.2 (count-prefixed cell lists)
  bool points_float64 = false;
};
// Arrays with 1 component become SCALARS, 3 components VECTORS, others one FIELD entry each; all
// values as double. Array names must be non-empty and free of whitespace (else UsageError).
void write_vtk_legacy(const std::filesystem::path& file, const MeshData& mesh,
                      const VtkLegacyWriteOptions& options = {});

}  // namespace vs
