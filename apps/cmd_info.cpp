#include <cstdio>

#include "commands.h"
#include "volstream/cuda/scene_bytes.h"
#include "volstream/io/dataset_info.h"
#include "volstream/render/integrators/umesh_renderer.h"

namespace vs::cli {
namespace {

// What a GPU render of one field at 512x512 allocates on the device (DeviceScene).
void add_device_bytes(const Dataset& ds, nlohmann::json& summary) {
  uint64_t total = 0;
  for (const auto& [structure, bytes] : cuda::device_scene_bytes(ds.topology(), 1, 512, 512)) {
    summary["device_bytes"][structure] = bytes;
    total += bytes;
  }
  summary["device_bytes"]["total (one field, 512x512)"] = total;
}

// What the renderer keeps resident for the mesh (topology, one field, acceleration structures;
// built here, as a render would) and that divided by the elements: bytes_per_element.
void add_mesh_resident_bytes(const Dataset& ds, nlohmann::json& summary) {
  const WorldTransform& transform = ds.manifest().transform;
  const MacroCells* cells = ds.macrocells();
  UMeshRenderer renderer = ds.is_compact_mesh() ? UMeshRenderer(ds.compact_mesh(), transform, nullptr, cells)
                                                : UMeshRenderer(ds.mesh(), ds.mesh_accel(), transform, nullptr, cells);
  if (const RegionVertices* lists = ds.region_vertices(); lists && cells) renderer.take_region_vertices(*lists);
  const UMeshBytes b = renderer.bytes();
  if (ds.is_compact_mesh()) {
    summary["resident_bytes"] = {{"local_vertices", b.compact.vertices}, {"vertex_tables", b.compact.tables},
                                 {"corners", b.compact.corners},         {"leaves", b.compact.leaves},
                                 {"leaf_bvh_nodes", b.compact.nodes},    {"submeshes", b.compact.submeshes}};
    summary["leaf_bvh_nodes"] = ds.compact_mesh().nodes.size();
  } else {
    summary["resident_bytes"] = {{"vertices", b.vertices},
                                 {"elements", b.elements},
                                 {"element_bvh_nodes", b.bvh_nodes},
                                 {"element_bvh_items", b.bvh_items},
                                 {"face_neighbors", b.face_neighbors},
                                 {"tet_walk_records", b.tet_walk}};
    if (b.region_lists > 0) summary["resident_bytes"]["macrocell_vertex_lists"] = b.region_lists;
    summary["element_bvh_nodes"] = renderer.element_bvh().nodes.size();
  }
  summary["resident_bytes"]["macrocells"] = b.macrocells;
  summary["resident_bytes"]["one_field"] = b.field;
  summary["resident_bytes"]["total"] = b.total();
  summary["bytes_per_element"] = double(b.total()) / double(ds.manifest().mesh.elements);
  summary["macrocells"] = renderer.region_count();
  summary["acceleration_build_seconds"] = renderer.build_seconds();
}

}  // namespace

void add_info_command(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  auto as_json = std::make_shared<bool>(false);
  auto* cmd =
      app.add_subcommand("info", "Describe a dataset: domain, levels or elements, fields, steps, bricks, ABRs, memory");
  cmd->add_option("dataset", *dir, "dataset directory")->required();
  cmd->add_flag("--json", *as_json, "machine-readable output");
  cmd->callback([dir, as_json] {
    const Dataset ds(*dir);
    auto summary = dataset_summary(ds);
    if (ds.is_mesh()) {
      add_mesh_resident_bytes(ds, summary);
    } else {
      add_device_bytes(ds, summary);
    }
    const std::string text = *as_json ? summary.dump(2) + "\n" : format_summary(summary);
    std::fputs(text.c_str(), stdout);
  });
}

}  // namespace vs::cli
