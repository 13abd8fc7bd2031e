#include "volstream/io/dataset_info.h"

#include <algorithm>
#include <bit>
#include <cstdio>

#include "volstream/umesh/compact_store.h"
#include "volstream/umesh/element_bvh.h"

namespace vs {
using json = nlohmann::json;

std::vector<BrickHistogramBin> cells_per_brick_histogram(const std::vector<Brick>& bricks) {
  std::vector<uint64_t> counts(64, 0);
  for (const Brick& b : bricks) ++counts[size_t(std::bit_width(uint64_t(b.cell_count())) - 1)];
  size_t last = 0;
  for (size_t i = 0; i < counts.size(); ++i)
    if (counts[i]) last = i;
  std::vector<BrickHistogramBin> bins;
  for (size_t i = 0; i <= last && !bricks.empty(); ++i)
    bins.push_back({uint64_t(1) << i, (uint64_t(2) << i) - 1, counts[i]});
  return bins;
}

namespace {

json field_summary(const DatasetManifest& m) {
  json fields = json::array();
  for (const auto& f : m.fields) {
    Range r{INFINITY, -INFINITY};
    for (const Range& s : f.step_ranges) r = {std::min(r.lo, s.lo), std::max(r.hi, s.hi)};
    fields.push_back({{"name", f.name}, {"min", r.lo}, {"max", r.hi}});
  }
  return fields;
}

json mesh_summary(const Dataset& ds) {
  const DatasetManifest& m = ds.manifest();
  json j;
  j["kind"] = "umesh";
  j["path"] = ds.dir().string();
  j["source"] = m.source;
  const Box3<double> b = ds.mesh_world_bounds();
  j["domain"] = {{"lower", {b.lower.x, b.lower.y, b.lower.z}}, {"upper", {b.upper.x, b.upper.y, b.upper.z}}};
  j["vertices"] = m.mesh.vertices;
  j["elements"] = m.mesh.elements;
  for (int t = 0; t < 4; ++t) j["elements_by_type"][kTypeSlotNames[t]] = m.mesh.by_type[t];
  if (m.mesh.split())  // convert --split-into-tets: the source's elements
    for (int t = 0; t < 4; ++t) j["split_from"][kTypeSlotNames[t]] = m.mesh.split_from[t];
  j["steps"] = m.step_count();
  j["step_times"] = m.step_times;
  j["fields"] = field_summary(m);
  j["encoding"] = m.mesh.compact() ? "compact" : "reference";
  const uint64_t values = align_up(m.value_count() * sizeof(float));
  if (m.mesh.compact()) {
    j["local_vertices"] = m.mesh.local_vertices;
    for_each_compact_array(ds.compact_mesh(), [&](const char* file, const auto& array) {
      j["bytes"][file] = array.size() * sizeof(array[0]);
    });
  } else {
    // Every file of the reference encoding (docs/formats.md), the stored walk records among them.
    j["bytes"] = {{"mesh_vertices", m.mesh.vertices * sizeof(vec3f)},
                  {"mesh_elements", m.mesh.elements * sizeof(UElement)},
                  {"mesh_bvh_nodes", m.mesh.bvh_nodes * sizeof(ElementBvhNode)},
                  {"mesh_bvh_items", m.mesh.elements * sizeof(uint32_t)},
                  {"mesh_neighbors", m.mesh.elements * shape::kMaxFaces * sizeof(uint32_t)},
                  {"mesh_tet_walk", m.mesh.tet_walk_records * sizeof(TetWalkRecord)}};
    if (m.mesh.region_vertices > 0)
      j["bytes"]["mesh_region_lists"] =
          (m.mesh.macrocells + 1) * sizeof(uint64_t) + m.mesh.region_vertices * sizeof(uint32_t);
  }
  j["bytes"]["values_per_field_step"] = values;
  j["bytes"]["values_total"] = values * m.fields.size() * uint64_t(m.step_count());
  return j;
}

}  // namespace

json dataset_summary(const Dataset& ds) {
  if (ds.is_mesh()) return mesh_summary(ds);
  const DatasetManifest& m = ds.manifest();
  const AmrTopology& t = ds.topology();
  json j;
  j["kind"] = "amr";
  j["path"] = ds.dir().string();
  j["source"] = m.source;
  const vec3d lo = m.transform.to_world(vec3d(m.grid_bounds.lower)),
              hi = m.transform.to_world(vec3d(m.grid_bounds.upper));
  j["domain"] = {{"lower", {lo.x, lo.y, lo.z}},
                 {"upper", {hi.x, hi.y, hi.z}},
                 {"grid_lower", {m.grid_bounds.lower.x, m.grid_bounds.lower.y, m.grid_bounds.lower.z}},
                 {"grid_upper", {m.grid_bounds.upper.x, m.grid_bounds.upper.y, m.grid_bounds.upper.z}},
                 {"finest_cell_size", {m.transform.cell_size.x, m.transform.cell_size.y, m.transform.cell_size.z}}};
  j["cells"] = m.cell_count;
  for (const auto& l : m.levels)
    j["levels"].push_back({{"level", l.level}, {"width", 1 << l.level}, {"cells", l.cell_count}});
  j["steps"] = m.step_count();
  j["step_times"] = m.step_times;
  j["fields"] = field_summary(m);
  j["bricks"] = t.bricks.size();
  j["abrs"] = t.abrs.size();
  j["abr_brick_refs"] = t.abr_bricks.size();
  j["bricks_per_abr"] = t.abrs.empty() ? 0.0 : double(t.abr_bricks.size()) / double(t.abrs.size());
  for (const auto& bin : cells_per_brick_histogram(t.bricks))
    j["cells_per_brick_histogram"].push_back({{"min", bin.min_cells}, {"max", bin.max_cells}, {"bricks", bin.bricks}});
  const uint64_t values = align_up(m.cell_count * sizeof(float));
  j["bytes"] = {{"cells", m.cell_count * sizeof(Cell)},
                {"bricks", t.bricks.size() * sizeof(Brick)},
                {"abrs", t.abrs.size() * sizeof(Abr)},
                {"abr_brick_lists", t.abr_bricks.size() * sizeof(uint32_t)},
                {"abr_ranges_per_field_step", t.abrs.size() * sizeof(Range)},
                {"values_per_field_step", values},
                {"values_total", values * m.fields.size() * uint64_t(m.step_count())}};
  j["file_order"] = m.file_order;  // file-order copies of every step + file_index.bin (--file-order)
  if (m.file_order) {
    j["bytes"]["file_index"] = m.cell_count * sizeof(uint32_t);
    j["bytes"]["file_order_values_total"] = values * m.fields.size() * uint64_t(m.step_count());
  }
  return j;
}

namespace {
std::string human_bytes(double b) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  int u = 0;
  while (b >= 1024 && u < 4) b /= 1024, ++u;
  char buf[32];
  std::snprintf(buf, sizeof(buf), u ? "%.1f %s" : "%.0f %s", b, units[u]);
  return buf;
}

// printf into a std::string.
template <typename... Args>
void append(std::string& s, const char* fmt, Args... args) {
  char buf[512];
  std::snprintf(buf, sizeof(buf), fmt, args...);
  s += buf;
}

std::string format_fields_list(const json& j) {
  std::string s;
  append(s, "fields    %zu\n", j["fields"].size());
  for (const auto& f : j["fields"])
    append(s, "  %-20s [%g, %g]\n", f["name"].get<std::string>().c_str(), f["min"].get<double>(),
           f["max"].get<double>());
  return s;
}

std::string format_bytes(const json& j) {
  std::string s;
  for (const char* section : {"bytes", "resident_bytes", "device_bytes"}) {
    if (!j.contains(section)) continue;
    s += std::string(section) + "\n";
    for (const auto& [k, v] : j[section].items())
      append(s, "  %-27s %s\n", k.c_str(), human_bytes(double(v.get<uint64_t>())).c_str());
  }
  if (j.contains("bytes_per_element")) append(s, "bytes_per_element %.1f\n", j["bytes_per_element"].get<double>());
  return s;
}

std::string format_mesh_summary(const json& j) {
  std::string s;
  const auto& d = j["domain"];
  append(s, "domain    [%g, %g, %g] - [%g, %g, %g]\n", d["lower"][0].get<double>(), d["lower"][1].get<double>(),
         d["lower"][2].get<double>(), d["upper"][0].get<double>(), d["upper"][1].get<double>(),
         d["upper"][2].get<double>());
  append(s, "mesh      %llu vertices, %llu elements, %s encoding\n", (unsigned long long)j["vertices"].get<uint64_t>(),
         (unsigned long long)j["elements"].get<uint64_t>(), j.value("encoding", "reference").c_str());
  for (const auto& [type, count] : j["elements_by_type"].items())
    append(s, "  %-12s %12llu\n", type.c_str(), (unsigned long long)count.get<uint64_t>());
  if (j.contains("split_from")) {
    std::string from;
    for (const auto& [type, count] : j["split_from"].items())
      if (count.get<uint64_t>() > 0)
        from += (from.empty() ? "" : ", ") + std::to_string(count.get<uint64_t>()) + " " + type;
    append(s, "  split into tets at convert, from %s\n", from.c_str());
  }
  append(s, "steps     %d (t = %g .. %g)\n", j["steps"].get<int>(), j["step_times"].front().get<double>(),
         j["step_times"].back().get<double>());
  return s + format_fields_list(j) + format_bytes(j);
}

}  // namespace

std::string format_summary(const json& j) {
  std::string s;
  char buf[512];
  auto line = [&](const char* fmt, auto... args) {
    std::snprintf(buf, sizeof(buf), fmt, args...);
    s += buf;
  };
  line("dataset   %s\nsource    %s\n", j["path"].get<std::string>().c_str(), j["source"].get<std::string>().c_str());
  if (j.value("kind", "amr") == "umesh") return s + format_mesh_summary(j);
  const auto& d = j["domain"];
  line("domain    [%g, %g, %g] - [%g, %g, %g]  (finest cell %g x %g x %g)\n", d["lower"][0].get<double>(),
       d["lower"][1].get<double>(), d["lower"][2].get<double>(), d["upper"][0].get<double>(),
       d["upper"][1].get<double>(), d["upper"][2].get<double>(), d["finest_cell_size"][0].get<double>(),
       d["finest_cell_size"][1].get<double>(), d["finest_cell_size"][2].get<double>());
  line("cells     %llu in %zu levels\n", (unsigned long long)j["cells"].get<uint64_t>(), j["levels"].size());
  for (const auto& l : j["levels"])
    line("  level %2d (width %6d): %12llu cells\n", l["level"].get<int>(), l["width"].get<int>(),
         (unsigned long long)l["cells"].get<uint64_t>());
  line("steps     %d (t = %g .. %g)\n", j["steps"].get<int>(), j["step_times"].front().get<double>(),
       j["step_times"].back().get<double>());
  if (j.value("file_order", false))
    s += "file order yes: every step also in file order, plus file_index.bin (--file-order)\n";
  s += format_fields_list(j);
  line("bricks    %llu\nABRs      %llu (%.2f bricks per ABR)\n", (unsigned long long)j["bricks"].get<uint64_t>(),
       (unsigned long long)j["abrs"].get<uint64_t>(), j["bricks_per_abr"].get<double>());
  s += "cells per brick (histogram)\n";
  uint64_t most = 1;
  for (const auto& b : j["cells_per_brick_histogram"]) most = std::max(most, b["bricks"].get<uint64_t>());
  for (const auto& b : j["cells_per_brick_histogram"]) {
    const uint64_t n = b["bricks"].get<uint64_t>();
    const std::string bar(
        size_t(n ? 1 + 39.0 * std::log10(double(n)) / std::log10(double(std::max<uint64_t>(most, 2))) : 0), '#');
    line("  %8llu-%-8llu %10llu %s\n", (unsigned long long)b["min"].get<uint64_t>(),
         (unsigned long long)b["max"].get<uint64_t>(), (unsigned long long)n, bar.c_str());
  }
  return s + format_bytes(j);
}

}  // namespace vs
