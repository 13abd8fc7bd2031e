// What `volstream convert` takes, for every caller that converts (the command line, the Python
// module's load): AMReX plotfile directories (several = time steps), an ExaBrick cells file with
// scalar files, raw grids, unstructured meshes (.vtu, .vtk, .pvd, .ugrid). One place decides the
// format and opens the matching importer, so that both callers accept and refuse the same inputs.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "volstream/amr/source.h"
#include "volstream/io/dataset.h"
#include "volstream/io/mesh_convert.h"

namespace vs {

struct ImportRequest {
  std::vector<std::filesystem::path> inputs;
  std::string format = "auto";        // auto | plotfile | exabrick | raw | mesh
  bool series = false;                // ExaBrick scalars / raw files are time steps of one field (else fields)
  std::string field_name = "scalar";  // the field of a series or of a single raw file
  // Raw grids.
  std::vector<int> dims;  // X, Y, Z; empty: not a raw grid unless the file ends in .raw
  std::string raw_type = "float32";
  bool big_endian = false;
  std::vector<double> origin{0, 0, 0}, spacing{1, 1, 1};
  // Meshes (UGRID carries no data of its own): raw float32 per-point scalars.
  std::vector<RawScalars> scalars;
  // OpenFOAM cases' regions, Fluent cases' cell zones, Exodus files' element blocks, CGNS files'
  // zones, Gmsh files' physical groups of volumes, EnSight cases' parts: those to read (empty: all).
  std::vector<std::string> regions;
};

// The format of the inputs: `format` unless auto, else told from the first input (a plotfile
// directory, .cells, a mesh file name, .raw or dims given). InputError for a missing input or a
// directory that is a dataset already or not a plotfile; UsageError when it cannot be told.
std::string import_format(const ImportRequest& request);

// Converts the inputs into a dataset directory (convert_to_dataset or convert_mesh_to_dataset)
// and returns what was written, for the command line's report: "from <source>: <counts> (<times>)".
std::string import_to_dataset(const ImportRequest& request, const std::filesystem::path& out_dir,
                              const ConvertOptions& options = {});

}  // namespace vs
