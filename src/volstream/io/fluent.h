// ANSYS Fluent case and data files (the Fluent User's Guide appendix "Case and Data File
// Formats"): a case file (.cas, or .cas.gz) holding the mesh as nodes, cells and the faces
// between them, and data files (.dat, .dat.gz) holding the solution per cell. Read here: 3D cases,
// ASCII and binary sections (nodes 10/2010/3010, cells 12/2012/3012, faces 13/2013/3013, zone
// names 39/45), every cell zone (fluid and solid alike); each cell built from the faces that name
// it as their c0 or c1 cell and split as VTK's polyhedra are (umesh/polyhedra.h: a cell whose faces
// are those of a tet, pyramid, wedge or hex stays one). Data sections 300/2300/3300 on cell zones
// as cell data, named by their Fluent variable (SV_) id ("pressure", "temperature", SV_U, SV_V,
// SV_W as one vector "velocity", others "SV_<id>"); a variable without values on some cell zone is
// NaN (no data) on that zone, one on part of a zone's cells left out (summary() says which);
// face zones' values are skipped. Refused with one line: 2D cases,
// hanging-node adaption (cell and face trees, sections 58 and 59), non-conformal interface
// parents (61), node or cell ids out of range, unbalanced parentheses, a file cut short.
#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "volstream/umesh/mesh_data.h"

namespace vs {

class FixedMeshSplit;  // umesh/polyhedra.h

// A case file's name: .cas or .cas.gz (any case). A data file's: .dat or .dat.gz.
bool is_fluent_case_file(const std::filesystem::path& file);
bool is_fluent_data_file(const std::filesystem::path& file);

class FluentFile {
 public:
  // Reads the case file's mesh (InputError naming it for anything it does not read). Each data
  // file is one step, in the order given; with none given, the data file of the case's name
  // (NAME.dat or NAME.dat.gz beside NAME.cas) if there is one, else the mesh alone (one step
  // without values).
  // `zones`: the cell zones to read, by name (or id where a zone has no name); none: all. A face
  // between a zone read and another is then on the boundary, and the nodes of no face read are
  // left out.
  explicit FluentFile(const std::filesystem::path& case_file, std::vector<std::filesystem::path> data_files = {},
                      const std::vector<std::string>& zones = {});
  ~FluentFile();
  FluentFile(const FluentFile&) = delete;
  FluentFile& operator=(const FluentFile&) = delete;

  size_t step_count() const;  // at least 1
  // The data file's flow time ("(flow-time T)" among its settings, section 37) where every data
  // file has one; else the step's index.
  double step_time(size_t step) const;
  // The mesh with the step's cell values, polyhedra split (once for the series), checked
  // (check_mesh).
  MeshData read_step(size_t step);
  // read_step for the split mesh's last use (a convert's first step): the mesh is handed over,
  // not copied; read_step and take_step throw std::logic_error after it.
  MeshData take_step(size_t step);
  // The step's cell values alone, on read_step's cells.
  std::vector<MeshArray> read_cell_data(size_t step);
  // The file a step's values come from (the case file for a mesh alone).
  std::filesystem::path step_file(size_t step) const;
  // "2 cell zones (fluid, solid): hex x 8, tet x 48", and the variables with no data on a zone or
  // left out, for `info`.
  std::string summary() const;

 private:
  FixedMeshSplit& split_mesh();  // made at the first call

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vs
