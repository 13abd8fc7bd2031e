#include <algorithm>
#include <cstdio>

#include "commands.h"
#include "volstream/amr/demo.h"
#include "volstream/core/error.h"
#include "volstream/io/dataset.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/io/ugrid.h"
#include "volstream/io/vtk_legacy.h"
#include "volstream/io/vtu.h"
#include "volstream/umesh/mesh_pieces.h"

namespace vs::cli {

namespace {
void write_mesh_file(const std::filesystem::path& file, const MeshData& mesh) {
  const std::string name = file.filename().string();
  auto ends_with = [&](const std::string& suffix) {
    return name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends_with(".vtu")) return write_vtu(file, mesh);
  // As a parallel run writes it: four pieces, each with a layer of ghost cells.
  if (ends_with(".pvtu")) return write_pvtu(file, cut_into_pieces(mesh, 4, mesh.cell_count() / 16));
  if (ends_with(".vtk")) return write_vtk_legacy(file, mesh);
  if (ends_with(".lb8.ugrid")) return write_ugrid(file, mesh, UgridEncoding::lb8);
  if (ends_with(".b8.ugrid")) return write_ugrid(file, mesh, UgridEncoding::b8);
  if (ends_with(".lb4.ugrid")) return write_ugrid(file, mesh, UgridEncoding::lb4);
  if (ends_with(".ugrid")) return write_ugrid(file, mesh, UgridEncoding::ascii);
  throw UsageError("--write-mesh: cannot tell the format of " + name + " (.vtu, .pvtu, .vtk, .ugrid)");
}
}  // namespace

void add_demo_command(CLI::App& app) {
  struct Args {
    std::string name;
    double cells = 1e6;
    double elements = 1e5;
    std::vector<std::string> mesh_files;
    int steps = 4;
    std::string out;
    bool quiet = false;
    bool file_order = false;
    std::vector<std::string> fields;
    std::string encoding = "compact";  // meshes
    bool split_into_tets = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("demo", "Write a built-in procedural dataset (AMR: jet, cosmo; meshes: tets, mixed, holes)");
  cmd->add_option("name", args->name,
                  "jet | cosmo (AMR), tets | mixed | holes (unstructured meshes: a tet box; twisted hexes, "
                  "wedges and pyramids; a tet mesh with a cavity, a notch and a second part)")
      ->required()
      ->check(CLI::IsMember({"jet", "cosmo", "tets", "mixed", "holes"}));
  cmd->add_option("--cells", args->cells, "approximate number of leaf cells (1e5 .. 5e8 and more)")
      ->capture_default_str();
  cmd->add_option("--elements", args->elements, "mesh demos: approximate number of elements")->capture_default_str();
  cmd->add_option("--steps", args->steps, "number of time steps")->capture_default_str()->check(CLI::Range(1, 100000));
  cmd->add_option("-o,--output", args->out, "output dataset directory")->required();
  cmd->add_option("--write-mesh", args->mesh_files,
                  "mesh demos: also write step 0 as a mesh file (.vtu appended raw; .pvtu: four .vtu pieces with "
                  "ghost cells beside it, as a parallel writer's; .vtk binary 5.1; NAME.{lb8,b8,lb4}.ugrid or "
                  "ascii .ugrid: the format from the name); repeatable");
  cmd->add_flag("--file-order", args->file_order,
                "also write every step in the generator's cell order and the permutation to device order "
                "(file_index.bin), for the streaming pipeline's flatten pass (doubles the values on disk)");
  cmd->add_option("--fields", args->fields, "write only these fields (comma-separated; default: all)")->delimiter(',');
  cmd->add_option("--encoding", args->encoding,
                  "mesh demos: compact (paper 002's encoding) or reference (element BVH and face adjacency)")
      ->check(CLI::IsMember({"compact", "reference"}))
      ->capture_default_str();
  add_split_into_tets_flag(cmd, args->split_into_tets);
  cmd->add_flag("-q,--quiet", args->quiet, "no progress bar");
  cmd->callback([args] {
    if (is_mesh_demo(args->name)) {
      MeshDemoOptions o{args->name, uint64_t(std::clamp(args->elements, 0.0, 1e12)), args->steps};
      for (const std::string& file : args->mesh_files) write_mesh_file(file, make_mesh_demo(o, 0));
      auto series = make_mesh_demo_series(o);
      const MeshConvertStats stats = convert_mesh_to_dataset(
          *series, args->out,
          {args->quiet, args->file_order, args->fields, parse_mesh_encoding(args->encoding), args->split_into_tets});
      std::printf(
          "wrote %s: demo %s, %llu elements, %llu vertices, %d steps (mesh %.2fs, encode %.2fs, values %.2fs)\n",
          args->out.c_str(), args->name.c_str(), (unsigned long long)stats.elements, (unsigned long long)stats.vertices,
          args->steps, stats.read_seconds, stats.encode_seconds, stats.values_seconds);
      return;
    }
    // Before the demo is generated (minutes for billions of cells); at least one field.
    const uint64_t fields = std::max<uint64_t>(1, args->fields.size());
    check_free_space(args->out, uint64_t(std::clamp(args->cells, 0.0, 1e12)),
                     uint64_t(args->steps) * fields * (args->file_order ? 2 : 1), args->file_order);
    auto source = make_demo({args->name, uint64_t(args->cells), args->steps});
    const ConvertStats stats = convert_to_dataset(*source, args->out, {args->quiet, args->file_order, args->fields});
    std::printf("wrote %s: %s, %llu cells, %d steps%s (cells %.2fs, bricks %.2fs, ABRs %.2fs, values %.2fs)\n",
                args->out.c_str(), source->description().c_str(), (unsigned long long)source->cell_count(), args->steps,
                args->file_order ? " + file-order copies" : "", stats.cells_seconds, stats.bricks_seconds,
                stats.abrs_seconds, stats.values_seconds);
  });
}

}  // namespace vs::cli
