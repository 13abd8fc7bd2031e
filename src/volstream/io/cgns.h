// CGNS (the CFD General Notation System: SU2, FUN3D, CFD++, STAR-CCM+'s and Fluent's export,
// Pointwise and ICEM meshes): one file (HDF5 or ADF, through Debian's CGNS library) holding a
// base of zones with their grids and flow solutions. Read here: the first base of cell dimension
// 3; its zones, unstructured (sections of TETRA_4, PYRA_5, PENTA_6, HEXA_8, the quadratic
// TETRA_10, PYRA_13, PENTA_15, HEXA_20, HEXA_27, and MIXED sections of them, turned into VTK's
// node orders; polyhedra, NFACE_n cells of NGON_n faces, split as VTK's (umesh/polyhedra.h);
// boundary sections of faces, edges and nodes left out) and structured (each cell a
// hexahedron), joined into one mesh (umesh/mesh_pieces.h: nodes the zones share welded; a field
// some zones lack NaN, no data, on theirs);
// FlowSolution nodes at Vertex (point data) and CellCenter (cell data), three fields NAMEX,
// NAMEY, NAMEZ as one vector NAME; time steps from BaseIterativeData's TimeValues and each
// zone's FlowSolutionPointers, else one step holding every solution. Refused with one line:
// NGON_n faces without NFACE_n cells, other element types, rind planes, solutions at other
// locations, a file without a 3D base.
#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "volstream/umesh/mesh_data.h"

namespace vs {

// False when this volstream was built without the CGNS library (then CgnsFile refuses every
// file, saying so).
bool cgns_supported();

class CgnsFile {
 public:
  // Reads the file's structure and grids (InputError naming the file for anything it does not
  // read). The file is read whole in a child process first (io/solver_files.h: HDF5 reads some
  // damaged files unsafely). `zones`: the zones to read, by name, and not the others (a name the
  // base lacks is refused, listing its zones); empty: all.
  explicit CgnsFile(const std::filesystem::path& file, const std::vector<std::string>& zones = {});
  ~CgnsFile();
  CgnsFile(const CgnsFile&) = delete;
  CgnsFile& operator=(const CgnsFile&) = delete;

  size_t step_count() const;  // at least 1
  double step_time(size_t step) const;
  // The zones joined with the step's solutions, quadratic elements split, checked.
  MeshData read_step(size_t step);
  // "2 zones, 1 structured: HEXA_8 x 64, HEXA_8 (structured) x 24, TETRA_4 x 48", for `info`.
  std::string summary() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vs
