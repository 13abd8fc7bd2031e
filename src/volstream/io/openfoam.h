// OpenFOAM case directories (the OpenFOAM User Guide's "OpenFOAM file format" and "Mesh
// description"), read natively, without foamToVTK: the mesh of constant/polyMesh (points,
// faces, owner, neighbour; each possibly .gz), ascii or binary as each file's FoamFile header
// says (format, and arch "label=32|64;scalar=32|64", MSB or LSB), faces as faceList or
// faceCompactList; each cell built from the faces that name it as their owner or neighbour and
// split as VTK's polyhedra are (umesh/polyhedra.h: a cell whose faces are those of a tet,
// pyramid, wedge or hex stays one), once for the whole series. Time steps: the numeric
// directories beside constant that hold volScalarField or volVectorField files (their
// internalField uniform or nonuniform, ascii or binary), by value, "0" included; the values are
// cell data named by their file (a volVectorField a 3-component array). A field missing from
// some step is left out, and point, surface and tensor fields are skipped (summary() says
// which).
// A decomposed case (no constant/polyMesh, but processor0 .. processorN-1, as decomposePar
// writes them; ParaView's "Decomposed Case") is read as reconstructPar would join it, without
// running it: each processor's mesh read as above, its points numbered as the whole mesh's by
// its constant/polyMesh/pointProcAddressing (so a point that processors share is one point, and
// the cell values averaged to it show no seam), its cells built from its own faces (those
// between processors, which both sides have, the other way round, each side's alone), the cells
// in processor order; the time steps are processor0's time directories, each field the
// processors' values one after another, kept where every processor has it. A case with both
// (its own mesh and processors, as one run in parallel from a whole mesh) is read from its
// processors where their last time is later than its own, else from its own mesh.
// A collated decomposed case (decomposePar -fileHandler collated: every processor's files in
// one directory processors<N>, each file the N processors' blocks one after another) is read as
// the same case uncollated, each file read once.
// A multi-region case (chtMultiRegionFoam's: a mesh in constant/REGION/polyMesh for each region,
// as splitMeshRegions writes them, fields in TIME/REGION; decomposed too, as decomposePar
// -allRegions writes it) is read as one mesh of every region, by name, or of those asked for
// (region0 is constant/polyMesh, which such a case keeps as the mesh before the split and is
// otherwise not read); the regions share no points, so values averaged to the points stay
// within each region; a field that some region lacks is NaN (no data) in that region.
// Refused with one line: a moving or changing mesh (a polyMesh with points or faces in a time
// directory), unknown formats or classes, lists cut short or larger than their file, face
// vertices, owners or neighbours out of range, faces of fewer than 3 vertices, cells of fewer
// than 4 faces, unbalanced parentheses; for a decomposed case also a gap in the processor
// numbers, a missing pointProcAddressing (decomposePar writes it; or run reconstructParMesh and
// reconstructPar), one of another length than the points or with numbers out of range, a point
// of the whole mesh in no processor, a shared point whose processors put it in places more than
// a relative 1e-9 apart, a time step that some processor lacks; for a collated case a file that
// is not a decomposedBlockData of as many blocks as processors<N> counts, a block cut short,
// two collated decompositions, one over I/O ranks (processors<N>_<first>-<last>); a region
// asked for that the case lacks.
#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "volstream/umesh/mesh_data.h"

namespace vs {

class FixedMeshSplit;  // umesh/polyhedra.h

// An input that names an OpenFOAM case: its directory (holding constant/polyMesh, a
// system/controlDict, or a processor0 or processors<N> directory, for a decomposed case), a file named *.foam or
// *.OpenFOAM in it (ParaView's convention), or its system/controlDict.
bool is_openfoam_input(const std::filesystem::path& input);

class OpenFoamCase {
 public:
  // Reads the mesh and finds the time steps (InputError naming the file for anything it does
  // not read). `regions`: those to read (empty: every named region of a multi-region case, else
  // region0).
  explicit OpenFoamCase(const std::filesystem::path& input, const std::vector<std::string>& regions = {});
  ~OpenFoamCase();
  OpenFoamCase(const OpenFoamCase&) = delete;
  OpenFoamCase& operator=(const OpenFoamCase&) = delete;

  size_t step_count() const;            // at least 1 (the mesh alone where no time directory holds fields)
  double step_time(size_t step) const;  // the time directory's value
  // The mesh with the step's cell values, polyhedra split (once for the series), checked.
  MeshData read_step(size_t step);
  // read_step for the split mesh's last use (a convert's first step): the mesh is handed over,
  // not copied; read_step and take_step throw std::logic_error after it.
  MeshData take_step(size_t step);
  // The step's cell values alone, on read_step's cells.
  std::vector<MeshArray> read_cell_data(size_t step);
  // The step's time directory (processor0's for a decomposed case; the polyMesh directory for the
  // mesh alone).
  std::filesystem::path step_file(size_t step) const;
  std::filesystem::path case_directory() const;
  // "1234 cells, 3800 faces; fields p, U", the fields left out and skipped, for `info`; ", decomposed
  // into N processors" after the faces for a decomposed case; "; regions (cells) fluid 120, solid 80"
  // for a multi-region case, and the fields with no data in some region.
  std::string summary() const;

 private:
  FixedMeshSplit& split_mesh();  // made at the first call

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vs
