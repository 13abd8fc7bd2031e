// Exodus II (Sandia's finite-element format, written by MOOSE, Sierra, Cubit, ALEGRA, Nalu-Wind,
// deal.II and libMesh, and by SEACAS's converters): one NetCDF file holding the mesh and every
// time step of its nodal and element variables. Read here through the NetCDF library, so in
// each of its forms (classic, 64-bit offset, 64-bit data, NetCDF-4/HDF5 with compression):
// 3D meshes; element blocks of TETRA4, TETRA10, HEX8, HEX20, HEX27, WEDGE6, WEDGE15, PYRAMID5 and
// PYRAMID13 (node orders turned into VTK's; quadratic elements split as umesh/quadratic.h says);
// blocks of surface, line and point elements (SHELL, QUAD, TRI, BEAM, BAR, SPHERE, ...: what a
// model keeps beside its volume) are left out; nodal variables as point data and element
// variables as cell data, three consecutive variables NAME_x, NAME_y, NAME_z (or NAMEX, ...)
// as one vector NAME; an element variable without values on some block of volume elements is
// NaN (no data) there, one on no block left out (summary() says which). Refused with one line:
// 1D and 2D meshes, other element types
// (polyhedra, other node counts), node indices out of range, a classic file cut short.
#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "volstream/umesh/mesh_data.h"

namespace vs {

// False when this volstream was built without the NetCDF library (then ExodusFile refuses every
// file, saying so).
bool exodus_supported();

class ExodusFile {
 public:
  // Reads the header and the mesh (coordinates, element blocks); InputError naming the file for
  // anything it does not read (see above). `blocks`: the element blocks to read, by name (eb_names)
  // or id (eb_prop1), the nodes of no block read left out; none: every block; InputError for a
  // block the file lacks.
  explicit ExodusFile(const std::filesystem::path& file, const std::vector<std::string>& blocks = {});
  ~ExodusFile();
  ExodusFile(const ExodusFile&) = delete;
  ExodusFile& operator=(const ExodusFile&) = delete;

  // The file's time steps (`time_whole`); a file without any (a mesh alone) has one, at time 0.
  size_t step_count() const;
  double step_time(size_t step) const;
  // The mesh with the step's variables, quadratic elements split, checked (check_mesh).
  MeshData read_step(size_t step);
  // "classic", "64-bit offset", "64-bit data" or "NetCDF-4"; the element blocks' types and counts
  // ("HEX8 x 64, WEDGE6 x 12"), for `info`.
  std::string summary() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vs
