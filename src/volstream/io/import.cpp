#include "volstream/io/import.h"

#include <cstdio>

#include "volstream/core/error.h"
#include "volstream/io/exabrick.h"
#include "volstream/io/openfoam.h"
#include "volstream/io/plotfile.h"
#include "volstream/io/raw_grid.h"

namespace vs {
namespace fs = std::filesystem;

namespace {

vec3d three(const std::vector<double>& v, const char* what) {
  if (v.size() != 3) throw UsageError(std::string(what) + " expects X,Y,Z");
  return {v[0], v[1], v[2]};
}

std::unique_ptr<AmrSource> open_amr_source(const ImportRequest& r, const std::string& format) {
  const std::vector<fs::path>& paths = r.inputs;
  if (format == "plotfile") return open_plotfile_series(paths);
  if (format == "exabrick") {
    if (paths.size() < 2) throw UsageError("ExaBrick input needs a cells file followed by at least one scalar file");
    return open_exabrick(
        {paths.front(), std::vector<fs::path>(paths.begin() + 1, paths.end()), r.series, r.field_name});
  }
  if (format != "raw") throw UsageError("unknown format '" + format + "' (plotfile, exabrick, raw, mesh)");
  if (r.dims.size() != 3) throw UsageError("raw input needs the grid dims X,Y,Z");
  RawGridInput in;
  in.files = paths;
  in.dims = {r.dims[0], r.dims[1], r.dims[2]};
  in.type = parse_raw_type(r.raw_type);
  in.big_endian = r.big_endian;
  in.files_are_fields = !r.series && paths.size() > 1;
  in.field_name = r.field_name;
  in.origin = three(r.origin, "origin");
  in.spacing = three(r.spacing, "spacing");
  return open_raw_grid(in);
}

// " (<name> 1.23s, <name> 0.45s, <name> 0.06s)": the stage times of a conversion.
std::string seconds(const char* a_name, double a, const char* b_name, double b, const char* c_name, double c) {
  char text[160];
  std::snprintf(text, sizeof text, " (%s %.2fs, %s %.2fs, %s %.2fs)", a_name, a, b_name, b, c_name, c);
  return text;
}

}  // namespace

std::string import_format(const ImportRequest& r) {
  if (r.inputs.empty()) throw UsageError("no input to convert");
  if (r.format != "auto") return r.format;
  const fs::path& first = r.inputs.front();
  std::error_code ec;
  if (fs::is_directory(first, ec)) {
    if (fs::exists(first / "manifest.json", ec)) input_error(first.string(), "is already a volstream dataset");
    if (is_plotfile(first)) return "plotfile";
    if (is_openfoam_input(first)) return "mesh";
    input_error(first.string(),
                "directory is neither an AMReX plotfile (no plotfile Header) nor an OpenFOAM case "
                "(no constant/polyMesh, system/controlDict, processor0 or processors<N>)");
  }
  if (!fs::exists(first, ec)) input_error(first.string(), "does not exist");
  if (first.extension() == ".cells") return "exabrick";
  if (is_mesh_file(first)) return "mesh";
  if (first.extension() == ".raw" || !r.dims.empty()) return "raw";
  throw UsageError("cannot tell the format of " + first.string() + " (use --format plotfile|exabrick|raw|mesh)");
}

std::string import_to_dataset(const ImportRequest& r, const fs::path& out_dir, const ConvertOptions& options) {
  const std::string format = import_format(r);
  if (format == "mesh") {
    auto series = open_mesh_files(r.inputs, r.scalars, r.regions);
    const MeshConvertStats s = convert_mesh_to_dataset(*series, out_dir, options);
    return "from " + series->description() + ": " + std::to_string(s.elements) + " elements, " +
           std::to_string(s.vertices) + " vertices, " + std::to_string(series->step_count()) + " steps" +
           seconds("read", s.read_seconds, "encode", s.encode_seconds, "values", s.values_seconds);
  }
  if (!r.scalars.empty()) throw UsageError("scalars (NAME=FILE) apply to mesh input (.ugrid)");
  if (!r.regions.empty())
    throw UsageError(region_formats() +
                     (r.inputs.empty() ? "" : " (" + r.inputs.front().string() + " is none of them)"));
  if (options.split_into_tets) throw UsageError("--split-into-tets applies to mesh input");
  auto source = open_amr_source(r, format);
  const ConvertStats s = convert_to_dataset(*source, out_dir, options);
  return "from " + source->description() + ": " + std::to_string(source->cell_count()) + " cells" +
         (options.file_order ? " + file-order copies" : "") +
         seconds("bricks", s.bricks_seconds, "ABRs", s.abrs_seconds, "values", s.values_seconds);
}

}  // namespace vs
