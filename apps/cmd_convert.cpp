// convert: AMReX plotfiles, ExaBrick cells+scalars, raw grids, meshes -> native dataset directory
// (io/import.h decides the format and runs the importer).
#include <cstdio>

#include "commands.h"
#include "volstream/io/dataset.h"
#include "volstream/io/import.h"

namespace vs::cli {

namespace {
struct ConvertArgs {
  ImportRequest in;
  std::vector<std::string> inputs, scalars;  // scalars: meshes, NAME=FILE raw float32 per point
  std::string out;
  bool quiet = false, file_order = false;
  std::vector<std::string> fields;
  std::string encoding = "compact";  // meshes
  bool split_into_tets = false;
};
}  // namespace

void add_convert_command(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  ImportRequest& in = a->in;
  auto* cmd =
      app.add_subcommand("convert",
                         "Convert AMReX plotfiles, ExaBrick cells+scalars, raw grids or unstructured meshes "
                         "(.vtu, .pvtu, .vtm, .vtk, .pvd, .series, .ugrid, EnSight .case, Exodus II .exo, "
                         ".cgns, Gmsh .msh, Fluent .cas [.dat...], an OpenFOAM case directory or its .foam file) to a "
                         "volstream dataset");
  cmd->add_option("inputs", a->inputs,
                  "plotfile directories (several = time steps) | FILE.cells SCALARS... | raw files (several = fields, "
                  "or steps with --series) | mesh files (several = time steps) or one .pvd or .series")
      ->required();
  cmd->add_option("-o,--output", a->out, "output dataset directory")->required();
  cmd->add_option("--format", in.format,
                  "auto | plotfile | exabrick | raw | mesh (.vtu .pvtu .vtm .vtk .pvd .series .ugrid .case .exo .cgns "
                  ".msh .cas, an OpenFOAM case)")
      ->check(CLI::IsMember({"auto", "plotfile", "exabrick", "raw", "mesh"}))
      ->capture_default_str();
  cmd->add_option("--dims", in.dims, "raw grid dimensions X,Y,Z")->delimiter(',')->expected(3);
  cmd->add_option("--type", in.raw_type, "raw value type: uint8 uint16 int16 uint32 int32 float32 float64")
      ->capture_default_str();
  cmd->add_flag("--big-endian", in.big_endian, "raw values are big-endian");
  cmd->add_option("--origin", in.origin, "raw grid world origin X,Y,Z")->delimiter(',')->expected(3);
  cmd->add_option("--spacing", in.spacing, "raw grid cell size X,Y,Z")->delimiter(',')->expected(3);
  cmd->add_flag("--series", in.series, "several scalar/raw files are time steps of one field (default: fields)");
  cmd->add_option("--field", in.field_name, "field name for a series or a single raw file")->capture_default_str();
  cmd->add_flag("--file-order", a->file_order,
                "also write every step in the input's cell order and the permutation to device order (file_index.bin), "
                "for the streaming pipeline's flatten pass (doubles the values on disk)");
  cmd->add_option("--fields", a->fields, "keep only these fields (comma-separated; default: all)")->delimiter(',');
  cmd->add_option("--encoding", a->encoding,
                  "meshes: compact (paper 002's encoding, 16-bit local indices) or reference (32-byte elements, "
                  "element BVH and face adjacency: CUDA renders, comparisons)")
      ->check(CLI::IsMember({"compact", "reference"}))
      ->capture_default_str();
  add_split_into_tets_flag(cmd, a->split_into_tets);
  cmd->add_flag("-q,--quiet", a->quiet, "no progress bar");
  cmd->add_option("--scalars", a->scalars,
                  "meshes (UGRID): NAME=FILE, a raw little-endian float32 file of one value per point; repeatable");
  cmd->add_option(
      "--region", a->in.regions,
      "a part of the model to read (repeatable): an OpenFOAM case's region (region0 is "
      "constant/polyMesh), a Fluent case's cell zone, an Exodus file's element block (name or id), a "
      "CGNS file's zone, a Gmsh file's physical group of volumes (name or number), an EnSight case's "
      "part (description or number), a .vtm's block (name, or path of names: fluid/internal); default: all, "
      "joined");
  cmd->callback([a] {
    a->in.inputs.assign(a->inputs.begin(), a->inputs.end());
    for (const std::string& s : a->scalars) a->in.scalars.push_back(parse_raw_scalars(s));
    ConvertOptions options{a->quiet, a->file_order, a->fields, parse_mesh_encoding(a->encoding), a->split_into_tets};
    const std::string report = import_to_dataset(a->in, a->out, options);
    std::printf("wrote %s %s\n", a->out.c_str(), report.c_str());
  });
}

}  // namespace vs::cli
