// AFLR3 / FUN3D UGRID volume grids, and raw per-point scalars to go with them.
//
// Layout (UG_IO "UGRID 3D Grid File Type", simcenter.msstate.edu/software/documentation/ug_io/
// 3d_grid_file_type_ugrid.html): seven counts (nodes, surface trias, surface quads, tets,
// pyramids "pents_5", prisms "pents_6", hexes), the x y z of every node, the surface tria and quad
// connectivity, one surface id per surface face, then the connectivity of the tets, pyramids,
// prisms and hexes, all node indices 1-based. Optional trailing records (reconnection flags, BL
// data) are ignored. Surface faces only bound the volume, so they are read and dropped.
//
// Encoding from the file name: name.ugrid ascii, name.b8.ugrid big endian, name.lb8.ugrid little
// endian (4-byte ints, 8-byte reals), name.b4.ugrid / name.lb4.ugrid the same with 4-byte reals
// (C stream files, no Fortran record marks; .r8/.lr8/... Fortran files are refused).
//
// Vertex order. Tets, prisms and hexes are stored in VTK's order; pyramids are not. We follow the
// UG_IO element connectivity document ("UG_IO : 3D input/output grids",
// simcenter.msstate.edu/software/documentation/ug_io/3d_input_output_grids.html, also
// simcenter.msstate.edu/docs/solidmesh/ugridconnectivity.html) as transcribed by meshio's UGRID
// reader (meshio/ugrid/_ugrid.py, which cites that page): a UGRID pyramid has its apex at node 3
// and its quad base on nodes 1-2-5-4, and converts to VTK as
//     VTK (0..4) = UGRID (2, 1, 4, 5, 3)        (1-based UGRID nodes; apex last in VTK)
// which turns the base around so that its right-hand normal points at the apex as VTK requires.
// A UGRID prism is nodes 1-2-3 (one triangle) and 4-5-6 above them, the same as VTK's wedge, so
// it is copied as is. The stored copy of the UG_IO page we could read did not include the
// element figures themselves; the tests pin this mapping down geometrically (positive volume,
// apex at VTK vertex 4).
#pragma once
#include <filesystem>
#include <string>

#include "volstream/umesh/mesh_data.h"

namespace vs {

// Encoding from the name's suffix; InputError for anything but the encodings listed above.
MeshData read_ugrid(const std::filesystem::path& file);

enum class UgridEncoding { ascii, b8, lb8, lb4, b4 };
// Writes the volume cells grouped by type (tets, pyramids, prisms, hexes: the order UGRID
// stores them in, so a mesh already in that order reads back identically) and no surface faces.
// Point and cell data are not part of the format. UsageError for other cell types.
void write_ugrid(const std::filesystem::path& file, const MeshData& mesh, UgridEncoding encoding);

// A point array `name` read from a raw little-endian float32 file holding exactly one value for
// each of `points` (else InputError naming the file, with expected and actual sizes).
MeshArray read_raw_scalars(uint64_t points, const std::string& name, const std::filesystem::path& raw_f32);
// The same array appended to the mesh's point data.
void attach_raw_scalars(MeshData& mesh, const std::string& name, const std::filesystem::path& raw_f32);

}  // namespace vs
