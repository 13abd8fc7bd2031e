// convert: AMReX plotfiles, ExaBrick cells+scalars, raw grids, meshes -> native dataset directory.
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "volstream/core/error.h"
#include "volstream/io/dataset.h"
#include "volstream/io/exabrick.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/io/plotfile.h"
#include "volstream/io/raw_grid.h"

namespace vs::cli {
namespace fs = std::filesystem;

namespace {
struct ConvertArgs {
  std::vector<std::string> inputs;
  std::string out, format = "auto";
  std::vector<int> dims;
  std::string raw_type = "float32";
  bool big_endian = false, series = false, quiet = false, file_order = false;
  std::vector<std::string> fields;
  std::string field_name = "scalar";
  std::vector<double> origin{0, 0, 0}, spacing{1, 1, 1};
  std::vector<std::string> scalars;  // meshes: NAME=FILE raw float32 per point
};

std::string detect_format(const ConvertArgs& a) {
  const fs::path first = a.inputs.front();
  std::error_code ec;
  if (fs::is_directory(first, ec)) {
    if (fs::exists(first / "manifest.json", ec)) input_error(first.string(), "is already a volstream dataset");
    if (is_plotfile(first)) return "plotfile";
    input_error(first.string(), "directory is not an AMReX plotfile (no plotfile Header)");
  }
  if (!fs::exists(first, ec)) input_error(first.string(), "does not exist");
  const std::string ext = first.extension().string();
  if (ext == ".cells") return "exabrick";
  if (is_mesh_file(first)) return "mesh";
  if (ext == ".raw" || !a.dims.empty()) return "raw";
  throw UsageError("cannot tell the format of " + first.string() + " (use --format plotfile|exabrick|raw)");
}

std::unique_ptr<AmrSource> open_source(const ConvertArgs& a) {
  const std::string format = a.format == "auto" ? detect_format(a) : a.format;
  std::vector<fs::path> paths(a.inputs.begin(), a.inputs.end());
  if (format == "plotfile") return open_plotfile_series(paths);
  if (format == "exabrick") {
    if (paths.size() < 2) throw UsageError("ExaBrick input needs a cells file followed by at least one scalar file");
    ExaBrickInput in{paths.front(), std::vector<fs::path>(paths.begin() + 1, paths.end()), a.series, a.field_name};
    return open_exabrick(in);
  }
  if (a.dims.size() != 3) throw UsageError("raw input needs --dims X,Y,Z");
  RawGridInput in;
  in.files = paths;
  in.dims = {a.dims[0], a.dims[1], a.dims[2]};
  in.type = parse_raw_type(a.raw_type);
  in.big_endian = a.big_endian;
  in.files_are_fields = !a.series && paths.size() > 1;
  in.field_name = a.field_name;
  in.origin = {a.origin[0], a.origin[1], a.origin[2]};
  in.spacing = {a.spacing[0], a.spacing[1], a.spacing[2]};
  return open_raw_grid(in);
}
void convert_mesh(const ConvertArgs& a) {
  std::vector<RawScalars> scalars;
  for (const std::string& s : a.scalars) scalars.push_back(parse_raw_scalars(s));
  auto series = open_mesh_files(std::vector<fs::path>(a.inputs.begin(), a.inputs.end()), scalars);
  const MeshConvertStats stats = convert_mesh_to_dataset(*series, a.out, {a.quiet, a.file_order, a.fields});
  std::printf("wrote %s from %s: %llu elements, %llu vertices, %d steps (read %.2fs, encode %.2fs, values %.2fs)\n",
              a.out.c_str(), series->description().c_str(), (unsigned long long)stats.elements,
              (unsigned long long)stats.vertices, series->step_count(), stats.read_seconds, stats.encode_seconds,
              stats.values_seconds);
}
}  // namespace

void add_convert_command(CLI::App& app) {
  auto a = std::make_shared<ConvertArgs>();
  auto* cmd = app.add_subcommand("convert",
                                 "Convert AMReX plotfiles, ExaBrick cells+scalars, raw grids or unstructured meshes "
                                 "(.vtu, .vtk, .pvd, .ugrid) to a volstream dataset");
  cmd->add_option("inputs", a->inputs,
                  "plotfile directories (several = time steps) | FILE.cells SCALARS... | raw files (several = fields, "
                  "or steps with --series) | mesh files (several = time steps) or one .pvd")
      ->required();
  cmd->add_option("-o,--output", a->out, "output dataset directory")->required();
  cmd->add_option("--format", a->format, "auto | plotfile | exabrick | raw | mesh (.vtu .vtk .pvd .ugrid)")
      ->check(CLI::IsMember({"auto", "plotfile", "exabrick", "raw", "mesh"}))
      ->capture_default_str();
  cmd->add_option("--dims", a->dims, "raw grid dimensions X,Y,Z")->delimiter(',')->expected(3);
  cmd->add_option("--type", a->raw_type, "raw value type: uint8 uint16 int16 uint32 int32 float32 float64")
      ->capture_default_str();
  cmd->add_flag("--big-endian", a->big_endian, "raw values are big-endian");
  cmd->add_option("--origin", a->origin, "raw grid world origin X,Y,Z")->delimiter(',')->expected(3);
  cmd->add_option("--spacing", a->spacing, "raw grid cell size X,Y,Z")->delimiter(',')->expected(3);
  cmd->add_flag("--series", a->series, "several scalar/raw files are time steps of one field (default: fields)");
  cmd->add_option("--field", a->field_name, "field name for a series or a single raw file")->capture_default_str();
  cmd->add_flag("--file-order", a->file_order,
                "also write every step in the input's cell order and the permutation to device order (file_index.bin), "
                "for the streaming pipeline's flatten pass (doubles the values on disk)");
  cmd->add_option("--fields", a->fields, "keep only these fields (comma-separated; default: all)")->delimiter(',');
  cmd->add_flag("-q,--quiet", a->quiet, "no progress bar");
  cmd->add_option("--scalars", a->scalars,
                  "meshes (UGRID): NAME=FILE, a raw little-endian float32 file of one value per point; repeatable");
  cmd->callback([a] {
    if ((a->format == "auto" ? detect_format(*a) : a->format) == "mesh") {
      convert_mesh(*a);
      return;
    }
    if (!a->scalars.empty()) throw UsageError("--scalars applies to mesh input (.ugrid)");
    auto source = open_source(*a);
    const ConvertStats stats = convert_to_dataset(*source, a->out, {a->quiet, a->file_order, a->fields});
    std::printf("wrote %s from %s: %llu cells%s (bricks %.2fs, ABRs %.2fs, values %.2fs)\n", a->out.c_str(),
                source->description().c_str(), (unsigned long long)source->cell_count(),
                a->file_order ? " + file-order copies" : "", stats.bricks_seconds, stats.abrs_seconds,
                stats.values_seconds);
  });
}

}  // namespace vs::cli
