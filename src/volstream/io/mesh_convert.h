// Unstructured meshes into the native dataset (kind umesh, docs/formats.md): the mesh of the
// first step is checked and encoded once (umesh/from_mesh_data.h); every later step must have
// the same mesh (a time series changes only its scalars) and contributes its fields.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "volstream/io/dataset.h"
#include "volstream/umesh/demo.h"
#include "volstream/umesh/mesh_data.h"

namespace vs {

// The data of a time step on a mesh known already.
struct StepData {
  std::vector<MeshArray> point_data, cell_data;
};

class MeshSeries {
 public:
  virtual ~MeshSeries() = default;
  virtual int step_count() const = 0;
  virtual double step_time(int step) const { return double(step); }
  virtual MeshData read_step(int step) = 0;  // checked with check_mesh
  // read_step(0) for a convert, which reads the first step once: a series may hand over what
  // it would otherwise copy (a solver case's split mesh), after which read_step may fail.
  virtual MeshData read_first_step() { return read_step(0); }
  // The data of a step whose mesh must be `first`'s (read_step(0)'s; InputError naming
  // origin(step) when it is not). By default the whole step is read and its mesh compared; a
  // solver's case, whose mesh is read once for every step, reads only the data.
  virtual StepData read_step_data(int step, const MeshData& first);
  // True where read_step_data needs of `first` its point count alone (a solver's case), so that
  // a convert may let go of the first step's cells once it has built what it needs of them.
  virtual bool steps_need_points_alone() const { return false; }
  virtual std::string origin(int step) const = 0;  // the file named in errors about that step
  virtual std::string description() const = 0;     // for `info` ("VTK XML .vtu", "demo tets", ...)
};

std::unique_ptr<MeshSeries> make_mesh_demo_series(const MeshDemoOptions& options);

// True for the file names the mesh readers take: .vtu, .pvtu, .vtm, .vtk, .pvd, .series (a
// ParaView file series of them), .ugrid (any UGRID encoding), .case (EnSight Gold, io/ensight.h),
// .exo, .e, .ex2, .exii, .g, .gen (Exodus II, io/exodus.h) and their rank files (NAME.N.R),
// .cgns, .cgn (CGNS, io/cgns.h), .msh (Gmsh, io/gmsh.h), .cas, .cas.gz
// (a Fluent case, io/fluent.h), an OpenFOAM case's directory, its .foam or .OpenFOAM file or its
// system/controlDict (io/openfoam.h).
bool is_mesh_file(const std::filesystem::path& file);

// Raw float32 per-point scalars for a UGRID grid (`--scalars NAME=FILE`).
struct RawScalars {
  std::string name;
  std::filesystem::path file;
};
// RawScalars from "NAME=FILE" (UsageError otherwise).
RawScalars parse_raw_scalars(const std::string& spec);
// The start of the usage error for --region on input it does not apply to: the formats it does.
std::string region_formats();

// The steps of mesh files: one .vtu/.pvtu/.vtm/.vtk/.ugrid file (one step), several (one step each, in
// the order given), or one .pvd collection or .series file (its steps, by time; a .pvd
// step's parts joined into one mesh, as the pieces of a .pvtu), or one EnSight Gold .case (its
// time steps; the geometry read once unless it changes), or one Exodus II file (its time
// steps; the mesh read once), or one or all rank files NAME.N.R of one (joined), or one CGNS
// file (its steps), or one Gmsh .msh file (its views' steps; several .msh files of one step
// each are a series like .vtu files), or one Fluent .cas and its .dat files (a step each, in the
// order given; none: the .dat of the case's name, if any), or one OpenFOAM case (its time
// directories; the mesh read and split once). `scalars` are attached to every
// step (UGRID carries no data of its own); `regions`: an OpenFOAM case's regions, a Fluent
// case's cell zones or an Exodus file's element blocks to read (UsageError for another input;
// empty: the reader's default, all). Headers are read when a
// step is read.
std::unique_ptr<MeshSeries> open_mesh_files(const std::vector<std::filesystem::path>& files,
                                            const std::vector<RawScalars>& scalars = {},
                                            const std::vector<std::string>& regions = {});

struct MeshConvertStats {
  double read_seconds = 0, encode_seconds = 0, values_seconds = 0;
  uint64_t elements = 0, vertices = 0;
};
MeshConvertStats convert_mesh_to_dataset(MeshSeries& series, const std::filesystem::path& out_dir,
                                         const ConvertOptions& options = {});

}  // namespace vs
