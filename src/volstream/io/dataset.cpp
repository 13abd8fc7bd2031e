#include "volstream/io/dataset.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "volstream/accel/refit.h"
#include "volstream/amr/abrs.h"
#include "volstream/amr/bricks.h"
#include "volstream/amr/ranges.h"
#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/core/progress.h"
#include "volstream/core/stopwatch.h"
#include "volstream/io/atomic_file.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/check_stamp.h"
#include "volstream/umesh/compact_store.h"
#include "volstream/umesh/subset.h"

namespace vs {
namespace fs = std::filesystem;
using json = nlohmann::json;

int DatasetManifest::field_index(const std::string& name) const {
  for (size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == name) return int(i);
  return -1;
}

MeshEncoding parse_mesh_encoding(const std::string& name) {
  if (name == "stored") return MeshEncoding::stored;
  if (name == "reference") return MeshEncoding::reference;
  if (name == "compact") return MeshEncoding::compact;
  throw UsageError("unknown mesh encoding '" + name + "' (stored, reference or compact)");
}

namespace dataset_files {
static std::string step_name(int step) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "step_%06d", step);
  return buf;
}
std::string field_values(const FieldInfo& f, int step) { return "fields/" + f.dir + "/" + step_name(step) + ".f32"; }
std::string field_ranges(const FieldInfo& f, int step) {
  return "fields/" + f.dir + "/" + step_name(step) + ".abr_ranges";
}
std::string field_file_order_values(const FieldInfo& f, int step) {
  return "fields/" + f.dir + "/" + step_name(step) + ".file_order.f32";
}
}  // namespace dataset_files

namespace {

// A field name made safe as a directory name; unique among the dataset's fields.
std::string field_dir_name(const std::string& name, size_t index) {
  std::string dir;
  for (char c : name) dir += (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-') ? c : '_';
  if (dir.empty() || dir.size() > 64) dir = "field";
  return std::to_string(index) + "_" + dir;
}

json to_json(const vec3d& v) { return json::array({v.x, v.y, v.z}); }
json to_json(const vec3i& v) { return json::array({v.x, v.y, v.z}); }

json manifest_to_json(const DatasetManifest& m) {
  json j;
  j["format"] = "volstream-amr";
  j["format_version"] = m.format_version;
  j["source"] = m.source;
  j["transform"] = {{"origin", to_json(m.transform.origin)}, {"cell_size", to_json(m.transform.cell_size)}};
  if (m.kind == DatasetKind::umesh) {
    j["kind"] = "umesh";
    j["vertex_count"] = m.mesh.vertices;
    j["element_count"] = m.mesh.elements;
    for (int t = 0; t < 4; ++t) j["elements_by_type"][kTypeSlotNames[t]] = m.mesh.by_type[t];
    if (m.mesh.split())
      for (int t = 0; t < 4; ++t) j["split_from"][kTypeSlotNames[t]] = m.mesh.split_from[t];
    if (m.mesh.macrocells) j["macrocells"] = m.mesh.macrocells;
    if (m.mesh.subcell_masks >= 0) j["subcell_masks"] = m.mesh.subcell_masks;
    if (m.mesh.compact()) {
      j["mesh_encoding"] = "compact";
      j["compact"] = {{"local_vertices", m.mesh.local_vertices},
                      {"leaf_parents", m.mesh.leaf_parents},
                      {"records", m.mesh.compact_records}};
    } else {
      j["mesh_encoding"] = "reference";
      j["bvh_node_count"] = m.mesh.bvh_nodes;
      if (m.mesh.tet_walk_records) j["tet_walk_records"] = m.mesh.tet_walk_records;
      if (m.mesh.region_vertices) j["region_vertices"] = m.mesh.region_vertices;
    }
  } else {
    j["kind"] = "amr";
    j["grid_bounds"] = {{"lower", to_json(m.grid_bounds.lower)}, {"upper", to_json(m.grid_bounds.upper)}};
    j["cell_count"] = m.cell_count;
    j["brick_count"] = m.brick_count;
    j["abr_count"] = m.abr_count;
    j["abr_brick_count"] = m.abr_brick_count;
    if (m.abr_bvh_node_count) j["abr_bvh_node_count"] = m.abr_bvh_node_count;
    if (m.abr_chunk_count) j["abr_chunk_count"] = m.abr_chunk_count;
    j["file_order"] = m.file_order;
    for (const auto& l : m.levels) j["levels"].push_back({{"level", l.level}, {"cells", l.cell_count}});
  }
  j["step_times"] = m.step_times;
  for (const auto& f : m.fields) {
    json ranges = json::array();
    for (const Range& r : f.step_ranges) ranges.push_back({r.lo, r.hi});
    j["fields"].push_back({{"name", f.name}, {"dir", f.dir}, {"step_ranges", ranges}});
  }
  return j;
}

template <typename T>
Vec3<T> vec_from_json(const json& j) {
  if (!j.is_array() || j.size() != 3) throw std::runtime_error("expected an array of 3 numbers");
  return {j[0].get<T>(), j[1].get<T>(), j[2].get<T>()};
}

DatasetManifest manifest_from_json(const json& j) {
  DatasetManifest m;
  if (j.at("format").get<std::string>() != "volstream-amr") throw std::runtime_error("not a volstream-amr manifest");
  m.format_version = j.at("format_version").get<int>();
  if (m.format_version != kDatasetFormatVersion)
    throw std::runtime_error("format version " + std::to_string(m.format_version) + " is not supported");
  m.source = j.at("source").get<std::string>();
  m.transform.origin = vec_from_json<double>(j.at("transform").at("origin"));
  m.transform.cell_size = vec_from_json<double>(j.at("transform").at("cell_size"));
  const std::string kind = j.value("kind", "amr");  // absent in datasets written before meshes
  if (kind == "umesh") {
    m.kind = DatasetKind::umesh;
    m.mesh.vertices = j.at("vertex_count").get<uint64_t>();
    m.mesh.elements = j.at("element_count").get<uint64_t>();
    for (int t = 0; t < 4; ++t) m.mesh.by_type[t] = j.at("elements_by_type").at(kTypeSlotNames[t]).get<uint64_t>();
    if (j.contains("split_from"))  // absent unless convert split the elements into tets
      for (int t = 0; t < 4; ++t) m.mesh.split_from[t] = j.at("split_from").at(kTypeSlotNames[t]).get<uint64_t>();
    m.mesh.macrocells = j.value("macrocells", uint64_t(0));              // absent before issue 17's mesh index
    m.mesh.subcell_masks = j.value("subcell_masks", int64_t(-1));        // absent before 2026-11-28
    const std::string encoding = j.value("mesh_encoding", "reference");  // absent before issue 13
    if (encoding == "compact") {
      const json& c = j.at("compact");
      m.mesh.encoding = MeshEncoding::compact;
      m.mesh.local_vertices = c.at("local_vertices").get<uint64_t>();
      m.mesh.leaf_parents = c.at("leaf_parents").get<uint64_t>();
      m.mesh.compact_records = c.at("records").get<std::map<std::string, uint64_t>>();
    } else if (encoding == "reference") {
      m.mesh.bvh_nodes = j.at("bvh_node_count").get<uint64_t>();
      m.mesh.tet_walk_records = j.value("tet_walk_records", uint64_t(0));  // absent before 2026-11-27
      m.mesh.region_vertices = j.value("region_vertices", uint64_t(0));    // absent before 2026-11-28
    } else {
      throw std::runtime_error("unknown mesh_encoding '" + encoding + "'");
    }
  } else if (kind == "amr") {
    m.grid_bounds.lower = vec_from_json<int32_t>(j.at("grid_bounds").at("lower"));
    m.grid_bounds.upper = vec_from_json<int32_t>(j.at("grid_bounds").at("upper"));
    m.cell_count = j.at("cell_count").get<uint64_t>();
    m.brick_count = j.at("brick_count").get<uint64_t>();
    m.abr_count = j.at("abr_count").get<uint64_t>();
    m.abr_brick_count = j.at("abr_brick_count").get<uint64_t>();
    m.abr_bvh_node_count = j.value("abr_bvh_node_count", uint64_t(0));
    m.abr_chunk_count = j.value("abr_chunk_count", uint64_t(0));  // absent before the ABR chunk index
    m.file_order = j.value("file_order", false);                  // absent in datasets written before it existed
    for (const auto& l : j.at("levels"))
      m.levels.push_back({l.at("level").get<int32_t>(), l.at("cells").get<uint64_t>()});
  } else {
    throw std::runtime_error("unknown dataset kind '" + kind + "'");
  }
  m.step_times = j.at("step_times").get<std::vector<double>>();
  for (const auto& f : j.at("fields")) {
    FieldInfo info{f.at("name").get<std::string>(), f.at("dir").get<std::string>(), {}};
    for (const auto& r : f.at("step_ranges")) info.step_ranges.push_back({r.at(0).get<float>(), r.at(1).get<float>()});
    m.fields.push_back(std::move(info));
  }
  return m;
}

}  // namespace

namespace {
std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", v);
  return text;
}
}  // namespace

std::string transform_problem(const WorldTransform& t) {
  for (int a = 0; a < 3; ++a) {
    const double size = t.cell_size[a], origin = t.origin[a];
    if (!(size > 0) || !std::isfinite(size) || !std::isfinite(origin))
      return "transform must be finite with positive cell size";
    // World positions are floats in the renderer: the grid (|coordinate| < 2^28) must map to
    // normal floats, and the origin must not swamp a cell (else rays cannot resolve cells).
    if (size < kMinCellSize || size > kMaxCellSize)
      return "cell size " + number(size) + " outside [1e-15, 1e15] world units";
    if (std::fabs(origin) > size * double(kMaxCoord) * 4)
      return "origin " + number(origin) + " is too far from the grid for its cell size";
  }
  return {};
}

namespace {
void validate_manifest(const DatasetManifest& m) {
  auto fail = [](const std::string& what) { throw std::runtime_error(what); };
  if (const std::string problem = transform_problem(m.transform); !problem.empty()) fail(problem);
  if (m.step_times.empty()) fail("no time steps");
  for (double t : m.step_times)
    if (!std::isfinite(t)) fail("non-finite step time");
  if (m.step_times.size() > 1000000) fail("too many time steps");
  if (m.fields.empty()) fail("no fields");
  for (const auto& f : m.fields) {
    if (f.step_ranges.size() != m.step_times.size())
      fail("field '" + f.name + "' has a range count unequal to the step count");
    for (const Range& r : f.step_ranges)
      if (!(std::isfinite(r.lo) && std::isfinite(r.hi) && r.lo <= r.hi))
        fail("field '" + f.name + "' has a non-finite or empty step range");
    if (f.dir.empty() || f.dir.find('/') != std::string::npos || f.dir.find("..") != std::string::npos)
      fail("field '" + f.name + "' has a bad directory name");
  }
  if (m.kind == DatasetKind::umesh) {
    const MeshCounts& c = m.mesh;
    if (c.vertices == 0 || c.elements == 0) fail("no vertices or elements");
    if (c.vertices >= kNoVertex || c.elements >= (uint64_t(1) << 32) / shape::kMaxFaces) fail("counts out of range");
    if (c.compact()) {
      // Each array at most what its elements could need; the files must have these sizes. The
      // most is compact_bytes.bin's: per element up to 8 corner bytes and 8 entries of 2 bytes in
      // its leaf's vertex table (a leaf of hexes has about 2 table entries an element: a 40^3
      // grid of hexes takes 13.5 bytes an element).
      if (c.local_vertices == 0 || c.local_vertices >= kNoVertex || c.leaf_parents >= kNoVertex)
        fail("compact counts out of range");
      for (const auto& [file, records] : c.compact_records)
        if (records > 24 * c.elements + c.local_vertices + 1) fail("compact record count of " + file + " out of range");
    } else if (c.bvh_nodes == 0 || c.bvh_nodes > 2 * c.elements) {
      fail("counts out of range");
    } else if (c.tet_walk_records != 0 && c.tet_walk_records != c.elements) {
      fail("tet_walk_records is neither 0 nor element_count");
    }
    if (c.macrocells > uint64_t(256 * 256 * 256)) fail("macrocell count out of range");
    if (c.region_vertices > kRegionVerticesBudget / sizeof(uint32_t) || (c.region_vertices > 0 && c.macrocells == 0))
      fail("region_vertices out of range");
    if (c.by_type[0] + c.by_type[1] + c.by_type[2] + c.by_type[3] != c.elements)
      fail("elements by type do not add up to element_count");
    return;
  }
  uint64_t level_cells = 0;
  for (const auto& l : m.levels) {
    if (l.level < 0 || l.level > kMaxLevel) fail("level out of range");
    level_cells += l.cell_count;
  }
  if (level_cells != m.cell_count) fail("cells per level do not add up to cell_count");
  // convert refuses input without cells, so an empty dataset is a damaged one.
  if (m.cell_count == 0 || m.brick_count == 0 || m.abr_count == 0) fail("no cells, bricks or ABRs");
  if (m.cell_count >= UINT32_MAX || m.brick_count > m.cell_count || m.abr_brick_count >= UINT32_MAX)
    fail("counts out of range");
  if (m.abr_bvh_node_count != 0 && m.abr_bvh_node_count != 2 * m.abr_count - 1)
    fail("abr_bvh_node_count does not match abr_count");
  if (m.abr_chunk_count != 0 && m.abr_chunk_count != chunk_count(m.abr_count))
    fail("abr_chunk_count does not match abr_count");
}

// An ABR lies inside the supports of the bricks it lists (it is a region where exactly those
// supports overlap) and its step width is their finest cell width. Checking both refuses NaN,
// infinite, inverted or stretched boxes (which the BVH build and the renderer cannot handle) and
// bounds the samples of a ray segment by the listed bricks' own extent in cells.
bool abr_geometry_ok(const AmrTopology& t, const Abr& a) {
  box3i hull = box3i::make_empty();
  int32_t finest = INT32_MAX;
  for (uint32_t k = 0; k < a.brick_count; ++k) {
    const Brick& b = t.bricks[t.abr_bricks[a.first_brick + k]];
    hull.extend(b.support_x2());
    finest = std::min(finest, b.width());
  }
  if (a.finest_width != float(finest)) return false;
  for (int axis = 0; axis < 3; ++axis) {
    const float lo2 = a.box.lower[axis] * 2.f, hi2 = a.box.upper[axis] * 2.f;  // half-grid units
    if (!(lo2 >= float(hull.lower[axis]) && hi2 <= float(hull.upper[axis]) && lo2 < hi2)) return false;  // also NaN
    if (lo2 != std::floor(lo2) || hi2 != std::floor(hi2)) return false;
  }
  return true;
}

// Bricks follow one another in the values (device order), inside the grid, and hold the
// manifest's cells.
void validate_bricks(const AmrTopology& t, const std::string& file) {
  uint64_t next = 0;
  for (const Brick& b : t.bricks) {
    bool ok = b.level >= 0 && b.level <= kMaxLevel && b.value_offset == next;
    for (int a = 0; a < 3 && ok; ++a)
      ok = b.dims[a] > 0 && b.dims[a] <= (1 << 20) && b.lower[a] > -kMaxCoord && b.lower[a] < kMaxCoord &&
           int64_t(b.lower[a]) + int64_t(b.dims[a]) * b.width() < kMaxCoord;
    if (!ok) input_error(file, "brick " + std::to_string(&b - t.bricks.data()) + " is invalid");
    next += uint64_t(b.cell_count());
    if (next > t.cell_count) break;  // reported below; also keeps the sum from overflowing
  }
  if (next != t.cell_count)
    input_error(file, "bricks hold " + std::to_string(next) + " cells, manifest says " + std::to_string(t.cell_count));
}

// The ABRs' brick lists name bricks and each ABR's geometry fits its bricks (abr_geometry_ok);
// `ids` (empty: the position) is each ABR's global index, for the report.
void validate_abrs(const AmrTopology& t, const std::string& file, const std::vector<uint32_t>& ids = {}) {
  for (uint32_t id : t.abr_bricks)
    if (id >= t.bricks.size()) input_error(file, "ABR brick index " + std::to_string(id) + " out of range");
  // Half a million ABRs on jet 1e6: checked on every core, the first bad one reported.
  std::atomic<uint64_t> first_bad{UINT64_MAX};
  parallel_for("check_abrs", int64_t(t.abrs.size()), [&](int64_t i) {
    const Abr& a = t.abrs[size_t(i)];
    if (uint64_t(a.first_brick) + a.brick_count > t.abr_bricks.size() || a.brick_count == 0 || !abr_geometry_ok(t, a)) {
      uint64_t seen = first_bad.load();
      while (uint64_t(i) < seen && !first_bad.compare_exchange_weak(seen, uint64_t(i))) {
      }
    }
  });
  if (const uint64_t bad = first_bad.load(); bad != UINT64_MAX)
    input_error(file, "ABR " + std::to_string(ids.empty() ? bad : ids[bad]) + " is invalid");
}

void validate_topology(const AmrTopology& t, const std::string& file) {
  validate_bricks(t, file);
  validate_abrs(t, file);
}

// Every element's used slots come first (4, 5, 6 or 8), name existing vertices and match the
// manifest's counts by type; every vertex is finite.
void check_finite_vertices(std::span<const vec3f> vertices, const std::string& file) {
  const int64_t bad = first_failing(int64_t(vertices.size()), [&](int64_t i) {
    const vec3f& v = vertices[size_t(i)];
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  });
  if (bad >= 0) input_error(file, "vertex " + std::to_string(bad) + " is not finite");
}

// Its used slots come first (4, 5, 6 or 8) and name existing vertices.
bool element_valid(const UElement& el, uint64_t vertex_count) {
  const int n = el.vertex_count();
  bool ok = true;
  for (int k = 0; k < 8; ++k) ok = ok && (k < n ? el.v[k] < vertex_count : el.v[k] == kNoVertex);
  return ok;
}

// Elements of each type (type_slot order), counted in parallel.
std::array<uint64_t, 4> count_by_type(std::span<const UElement> elements) {
  std::array<std::atomic<uint64_t>, 4> total{};
  parallel_for_ranges(
      int64_t(elements.size()),
      [&](int64_t begin, int64_t end) {
        uint64_t n[4] = {};
        for (int64_t e = begin; e < end; ++e) ++n[type_slot(elements[size_t(e)].vertex_count())];
        for (int t = 0; t < 4; ++t) total[size_t(t)] += n[t];
      },
      4096);
  return {total[0].load(), total[1].load(), total[2].load(), total[3].load()};
}

void validate_mesh(const UMesh& m, const MeshCounts& counts, const std::string& file) {
  check_finite_vertices(m.vertices, file);
  const int64_t bad = first_failing(int64_t(m.elements.size()),
                                    [&](int64_t e) { return element_valid(m.elements[size_t(e)], m.vertices.size()); });
  if (bad >= 0) input_error(file, "element " + std::to_string(bad) + " is invalid");
  const std::array<uint64_t, 4> by_type = count_by_type(m.elements);
  for (int t = 0; t < 4; ++t)
    if (by_type[t] != counts.by_type[t])
      input_error(file, std::string("the manifest's ") + kTypeSlotNames[t] + " count does not match the elements");
}

}  // namespace

// ---------------------------------------------------------------------------------------------
DatasetWriter::DatasetWriter(fs::path dir, DatasetManifest manifest, const std::vector<std::string>& field_names)
    : dir_(std::move(dir)), manifest_(std::move(manifest)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) input_error(dir_.string(), "cannot create directory: " + ec.message());
  for (size_t i = 0; i < field_names.size(); ++i) {
    FieldInfo f{field_names[i], field_dir_name(field_names[i], i), {}};
    f.step_ranges.assign(manifest_.step_times.size(), Range{INFINITY, -INFINITY});
    fs::create_directories(dir_ / "fields" / f.dir, ec);
    if (ec) input_error((dir_ / "fields" / f.dir).string(), "cannot create directory: " + ec.message());
    manifest_.fields.push_back(std::move(f));
  }
}

void DatasetWriter::write_topology(const AmrTopology& t, const std::vector<Cell>& device_cells) {
  topology_ = &t;
  manifest_.cell_count = t.cell_count;
  manifest_.brick_count = t.bricks.size();
  manifest_.abr_count = t.abrs.size();
  manifest_.abr_brick_count = t.abr_bricks.size();
  write_file(dir_ / dataset_files::kCells, device_cells.data(), device_cells.size() * sizeof(Cell));
  write_file(dir_ / dataset_files::kBricks, t.bricks.data(), t.bricks.size() * sizeof(Brick));
  write_file(dir_ / dataset_files::kAbrs, t.abrs.data(), t.abrs.size() * sizeof(Abr));
  write_file(dir_ / dataset_files::kAbrBricks, t.abr_bricks.data(), t.abr_bricks.size() * sizeof(uint32_t));
  write_abr_bvh(t);
  write_abr_chunks(t);
}

// What a data-parallel rank chooses ABRs by without reading them (28 bytes per 32 ABRs).
void DatasetWriter::write_abr_chunks(const AmrTopology& t) {
  const std::vector<AbrChunk> chunks = abr_chunks(t.abrs);
  manifest_.abr_chunk_count = chunks.size();
  write_file(dir_ / dataset_files::kAbrChunks, chunks.data(), chunks.size() * sizeof(AbrChunk));
}

// The BVH's topology only (8 bytes a node): the boxes are the ABRs' own and refit at load, which
// is cheap, while the SAH build is a quarter of a whole render of the jet demo (bench/RESULTS.md).
void DatasetWriter::write_abr_bvh(const AmrTopology& t) {
  const Bvh bvh = build_abr_bvh(t);
  std::vector<uint32_t> links;
  links.reserve(2 * bvh.nodes.size());
  for (const BvhNode& n : bvh.nodes) links.insert(links.end(), {n.index, n.is_leaf});
  manifest_.abr_bvh_node_count = bvh.nodes.size();
  write_file(dir_ / dataset_files::kAbrBvh, links.data(), links.size() * sizeof(uint32_t));
}

void DatasetWriter::write_mesh(const UMesh& mesh) {
  manifest_.kind = DatasetKind::umesh;
  manifest_.mesh.vertices = mesh.vertices.size();
  manifest_.mesh.elements = mesh.elements.size();
  for (int t = 0; t < 4; ++t) manifest_.mesh.by_type[t] = mesh.count_by_type[t];
  write_file(dir_ / dataset_files::kMeshVertices, mesh.vertices.data(), mesh.vertices.size() * sizeof(vec3f));
  write_file(dir_ / dataset_files::kMeshElements, mesh.elements.data(), mesh.elements.size() * sizeof(UElement));
  const MeshAccel accel = build_mesh_accel(mesh);
  manifest_.mesh.bvh_nodes = accel.bvh.nodes.size();
  write_file(dir_ / dataset_files::kMeshBvhNodes, accel.bvh.nodes.data(),
             accel.bvh.nodes.size() * sizeof(ElementBvhNode));
  write_file(dir_ / dataset_files::kMeshBvhItems, accel.bvh.items.data(), accel.bvh.items.size() * sizeof(uint32_t));
  write_file(dir_ / dataset_files::kMeshNeighbors, accel.neighbors.data(), accel.neighbors.size() * sizeof(uint32_t));
  // The CPU walk's records, so that a render maps them instead of building 64 B an element in
  // fresh memory (bench/RESULTS.md, "Walk records stored"); written block by block as made.
  if (has_tets(mesh)) {
    AtomicFile walk(dir_ / dataset_files::kMeshTetWalk);
    manifest_.mesh.tet_walk_records = for_each_tet_walk_block(
        mesh, accel.neighbors,
        [&](const TetWalkRecord* records, size_t count) { walk.write(records, count * sizeof(TetWalkRecord)); });
    walk.commit();
  } else {
    manifest_.mesh.tet_walk_records = 0;
  }
  // The vertices' bounds (those of a vertex of no element too: one process's world bounds),
  // then the chunk boxes: what a rank chooses its elements by (umesh/mesh_index.h).
  box3f bounds = box3f::make_empty();
  for (const vec3f& v : mesh.vertices) bounds.extend(v);
  std::vector<box3f> chunks = reference_chunk_boxes(mesh, accel.bvh.items);
  chunks.insert(chunks.begin(), bounds);
  write_file(dir_ / dataset_files::kMeshChunks, chunks.data(), chunks.size() * sizeof(box3f));
  const MacroCells cells = build_macrocells(mesh);
  write_macrocells(cells);
  write_region_vertices(region_vertices(mesh, cells));
}

void DatasetWriter::write_compact_mesh(const UMesh& mesh, const CompactMesh& compact) {
  manifest_.kind = DatasetKind::umesh;
  manifest_.mesh.encoding = MeshEncoding::compact;
  manifest_.mesh.vertices = mesh.vertices.size();
  manifest_.mesh.elements = mesh.elements.size();
  for (int t = 0; t < 4; ++t) manifest_.mesh.by_type[t] = mesh.count_by_type[t];
  manifest_.mesh.local_vertices = compact.vertices.size();
  manifest_.mesh.leaf_parents = compact.leaf_parents;
  for_each_compact_array(compact, [&](const char* file, const auto& array) {
    write_file(dir_ / file, array.data(), array.size() * sizeof(array[0]));
    manifest_.mesh.compact_records[file] = array.size();
  });
  write_macrocells(build_macrocells(compact));
}

// The grid, then the non-empty cells: what a rank chooses its leaves by (umesh/mesh_index.h).
void DatasetWriter::write_macrocells(const MacroCells& cells) {
  const std::vector<StoredMacrocell> stored = stored_macrocells(cells);
  std::vector<uint8_t> bytes(sizeof(MacroGrid) + stored.size() * sizeof(StoredMacrocell));
  std::memcpy(bytes.data(), &cells.grid, sizeof(MacroGrid));
  if (!stored.empty())
    std::memcpy(bytes.data() + sizeof(MacroGrid), stored.data(), stored.size() * sizeof(StoredMacrocell));
  write_file(dir_ / dataset_files::kMeshMacrocells, bytes.data(), bytes.size());
  manifest_.mesh.macrocells = stored.size();
  write_subcells(cells.subcells);
}

void DatasetWriter::write_subcells(const MacroCells::SubcellMasks& subcells) {
  const size_t index_bytes = subcells.of_region.size() * sizeof(uint32_t);
  std::vector<uint8_t> bytes(index_bytes + subcells.masks.size() * sizeof(SubcellMask));
  // An empty vector's data() may be null, which memcpy must not get even for no bytes.
  if (index_bytes > 0) std::memcpy(bytes.data(), subcells.of_region.data(), index_bytes);
  if (bytes.size() > index_bytes)
    std::memcpy(bytes.data() + index_bytes, subcells.masks.data(), bytes.size() - index_bytes);
  write_file(dir_ / dataset_files::kMeshSubcells, bytes.data(), bytes.size());
  manifest_.mesh.subcell_masks = int64_t(subcells.masks.size());
}

// Each macrocell's vertex list (none over the build's budget), so that a render's ranges read them
// instead of passing over the elements (umesh/macrocells.h).
void DatasetWriter::write_region_vertices(const std::optional<RegionVertices>& lists) {
  manifest_.mesh.region_vertices = 0;
  if (!lists || lists->vertex.empty()) return;
  write_file(dir_ / dataset_files::kMeshRegionFirst, lists->first.data(), lists->first.size() * sizeof(uint64_t));
  write_file(dir_ / dataset_files::kMeshRegionVertices, lists->vertex.data(), lists->vertex.size() * sizeof(uint32_t));
  manifest_.mesh.region_vertices = lists->vertex.size();
}

void DatasetWriter::write_values(int field, int step, const std::vector<float>& values) {
  write_values(field, step, values, value_range(values.data(), values.size()));
}

void DatasetWriter::write_values(int field, int step, const std::vector<float>& values, Range step_range) {
  FieldInfo& f = manifest_.fields.at(size_t(field));
  write_file(dir_ / dataset_files::field_values(f, step), values.data(), values.size() * sizeof(float), kFileAlignment);
  f.step_ranges.at(size_t(step)) = step_range;
  if (manifest_.kind == DatasetKind::umesh) return;  // mesh ranges are per macrocell, made at load
  const auto abr_ranges = compute_abr_ranges(*topology_, values.data());
  write_file(dir_ / dataset_files::field_ranges(f, step), abr_ranges.data(), abr_ranges.size() * sizeof(Range));
  f.step_ranges.at(size_t(step)) = value_range(values.data(), values.size());
}

void DatasetWriter::write_file_index(const std::vector<uint32_t>& index) {
  if (index.size() != manifest_.cell_count)
    throw std::logic_error("write_file_index: " + std::to_string(index.size()) + " entries for " +
                           std::to_string(manifest_.cell_count) + " cells");
  write_file(dir_ / dataset_files::kFileIndex, index.data(), index.size() * sizeof(uint32_t));
  manifest_.file_order = true;
}

void DatasetWriter::write_file_order_values(int field, int step, const float* values, uint64_t count) {
  if (count != manifest_.cell_count) throw std::logic_error("write_file_order_values: wrong value count");
  const FieldInfo& f = manifest_.fields.at(size_t(field));
  write_file(dir_ / dataset_files::field_file_order_values(f, step), values, count * sizeof(float), kFileAlignment);
}

void DatasetWriter::finish() {
  // Field names come from input files and may not be valid UTF-8: replace bad bytes (U+FFFD).
  const std::string text = manifest_to_json(manifest_).dump(1, ' ', false, json::error_handler_t::replace);
  write_file(dir_ / dataset_files::kManifest, text.data(), text.size());
}

// ---------------------------------------------------------------------------------------------
template <typename T>
std::vector<T> Dataset::read_topology(const fs::path& path, uint64_t count) {
  std::vector<T> records = read_records<T>(path, count);
  topology_bytes_read_ += count * sizeof(T);
  return records;
}

template <typename T>
HostArray<T> Dataset::map_topology(const fs::path& path, uint64_t count) {
  HostArray<T> records = map_records<T>(path, count);
  topology_bytes_read_ += count * sizeof(T);
  return records;
}

Dataset::Dataset(const fs::path& dir, TopologyLoad load) : dir_(dir) {
  const fs::path manifest_path = dir / dataset_files::kManifest;
  try {
    manifest_ = manifest_from_json(json::parse(read_text_file(manifest_path)));
    validate_manifest(manifest_);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    input_error(manifest_path.string(), std::string("bad manifest: ") + e.what());
  }
  if (manifest_.kind == DatasetKind::umesh) {
    deferred_ = load == TopologyLoad::deferred && manifest_.mesh.macrocells > 0;
    load_mesh();
    return;
  }
  load_amr(load);
  if (manifest_.file_order) {  // the index itself is read (and checked) by whoever needs it
    const fs::path index = dir / dataset_files::kFileIndex;
    const uint64_t size = file_size_checked(index);
    if (size != manifest_.cell_count * sizeof(uint32_t))
      throw_size_mismatch(index, size, manifest_.cell_count * sizeof(uint32_t));
  }
}

// The bricks, and then the ABRs, their lists and BVH; or deferred, the ABR chunk index instead.
void Dataset::load_amr(TopologyLoad load) {
  const std::string bricks_file = (dir_ / dataset_files::kBricks).string();
  topology_.cell_count = manifest_.cell_count;
  topology_.bricks = read_topology<Brick>(dir_ / dataset_files::kBricks, manifest_.brick_count);
  deferred_ = load == TopologyLoad::deferred && manifest_.abr_chunk_count > 0;
  if (deferred_) {
    validate_bricks(topology_, bricks_file);
    read_stored_abr_chunks();
  } else {
    // The stored BVH's tree is read and checked beside the ABRs and their lists (it needs only
    // their count), then refit to their boxes.
    const uint64_t bvh_nodes = manifest_.abr_bvh_node_count;
    parallel_invoke_in_order(
        [&] {
          topology_.abrs = read_topology<Abr>(dir_ / dataset_files::kAbrs, manifest_.abr_count);
          topology_.abr_bricks = read_topology<uint32_t>(dir_ / dataset_files::kAbrBricks, manifest_.abr_brick_count);
          validate_topology(topology_, bricks_file);
        },
        [&] {
          if (bvh_nodes) topology_.abr_bvh.nodes = read_abr_bvh_tree();
        });
    topology_bytes_read_ += bvh_nodes * 2 * sizeof(uint32_t);
    if (bvh_nodes) refit_bvh(topology_.abr_bvh.nodes, abr_boxes(topology_), {});
  }
  count_topology_bytes();
}

// Finite boxes and positive finite widths (a NaN would make the selection skip the chunk).
void Dataset::read_stored_abr_chunks() {
  const fs::path path = dir_ / dataset_files::kAbrChunks;
  stored_abr_chunks_ = read_topology<AbrChunk>(path, manifest_.abr_chunk_count);
  for (size_t i = 0; i < stored_abr_chunks_.size(); ++i) {
    const AbrChunk& c = stored_abr_chunks_[i];
    const box3f& b = c.box;
    if (!(b.lower.x <= b.upper.x && b.lower.y <= b.upper.y && b.lower.z <= b.upper.z && c.finest_width > 0) ||
        !std::isfinite(b.lower.x + b.lower.y + b.lower.z + b.upper.x + b.upper.y + b.upper.z + c.finest_width))
      input_error(path.string(), "chunk " + std::to_string(i) + " has no finite box or width");
  }
}

std::vector<AbrChunk> Dataset::abr_chunks() const {
  if (is_mesh() || part()) throw std::logic_error("Dataset::abr_chunks: not AMR, or already restricted");
  return stored_abr_chunks_.empty() ? vs::abr_chunks(topology_.abrs) : stored_abr_chunks_;
}

namespace {
// The stored walk records, mapped and checked when a CPU walk first asks for them: info, probes
// and CUDA frames never do, so they never pay for the pages.
// `mesh_files`: those the records are checked against (a stamp covers both, io/check_stamp.h).
TetWalkSource stored_tet_walk(fs::path path, uint64_t count, std::vector<fs::path> mesh_files) {
  return [path = std::move(path), count, mesh_files = std::move(mesh_files)](const UMesh& mesh,
                                                                             std::span<const uint32_t> neighbors) {
    const Stopwatch watch;
    // Const: a HostArray's non-const members copy a view (core/host_array.h).
    const auto records = std::make_shared<const HostArray<TetWalkRecord>>(map_records<TetWalkRecord>(path, count));
    std::vector<fs::path> files = mesh_files;
    files.push_back(path);
    const CheckStamp stamp("tet walk records", files);
    const bool checked = stamp.passed_before();
    if (!checked) {
      check_tet_walk_records(mesh, neighbors, *records, path.string());
      stamp.record();
    }
    launch_times().add(checked ? "stored tet walk records (stamp)" : "stored tet walk records", watch.seconds());
    return TetWalkRecords::view(records, records->data(), records->size());
  };
}
}  // namespace

void Dataset::load_mesh() {
  if (manifest_.mesh.compact()) return load_compact_mesh();
  if (deferred_) return load_reference_index();
  const std::string nodes_file = (dir_ / dataset_files::kMeshBvhNodes).string();
  const Stopwatch watch;
  // The arrays are mapped, not read (core/host_array.h), the vertices and elements beside the
  // BVH, adjacency and stored macrocells.
  parallel_invoke_in_order(
      [&] {
        mesh_.vertices = map_topology<vec3f>(dir_ / dataset_files::kMeshVertices, manifest_.mesh.vertices);
        mesh_.elements = map_topology<UElement>(dir_ / dataset_files::kMeshElements, manifest_.mesh.elements);
        for (int t = 0; t < 4; ++t) mesh_.count_by_type[t] = manifest_.mesh.by_type[t];
      },
      [&] {
        mesh_accel_.bvh.nodes =
            map_topology<ElementBvhNode>(dir_ / dataset_files::kMeshBvhNodes, manifest_.mesh.bvh_nodes);
        mesh_accel_.bvh.items = map_topology<uint32_t>(dir_ / dataset_files::kMeshBvhItems, manifest_.mesh.elements);
        mesh_accel_.neighbors =
            map_topology<uint32_t>(dir_ / dataset_files::kMeshNeighbors, manifest_.mesh.elements * shape::kMaxFaces);
        if (manifest_.mesh.macrocells > 0) read_stored_macrocells();
        if (manifest_.mesh.region_vertices > 0) map_stored_region_vertices();
      });
  if (manifest_.mesh.tet_walk_records > 0)
    mesh_accel_.stored_tet_walk =
        stored_tet_walk(dir_ / dataset_files::kMeshTetWalk, manifest_.mesh.tet_walk_records, mesh_files(false));
  count_mesh_bytes();
  // Checked once per version of the files (io/check_stamp.h), looked at after they were mapped:
  // a file replaced before its mapping does not match the stamp of the one it replaced.
  const CheckStamp stamp("reference mesh", mesh_files(manifest_.mesh.macrocells > 0));
  if (stamp.passed_before()) return launch_times().add("mesh checked before (stamp)", watch.seconds());
  // The BVH's and adjacency's structure needs only the element count: checked beside the elements.
  parallel_invoke_in_order(
      [&] { validate_mesh(mesh_, manifest_.mesh, (dir_ / dataset_files::kMeshElements).string()); },
      [&] { check_mesh_accel_structure(mesh_accel_, manifest_.mesh.elements, nodes_file); });
  check_mesh_accel_boxes(mesh_, mesh_accel_, nodes_file);
  const bool cells_as_stored = manifest_.mesh.macrocells == 0 || build_macrocells_on_stored_grid();
  check_stored_region_vertices();
  if (cells_as_stored) stamp.record();
}

void Dataset::map_stored_region_vertices() {
  RegionVertices lists;
  lists.first = map_topology<uint64_t>(dir_ / dataset_files::kMeshRegionFirst, manifest_.mesh.macrocells + 1);
  lists.vertex = map_topology<uint32_t>(dir_ / dataset_files::kMeshRegionVertices, manifest_.mesh.region_vertices);
  stored_region_vertices_ = std::move(lists);
}

void Dataset::check_stored_region_vertices() const {
  if (!stored_region_vertices_) return;
  const std::string fault = region_vertices_fault(mesh_, stored_cells_, *stored_region_vertices_);
  if (!fault.empty()) input_error((dir_ / dataset_files::kMeshRegionVertices).string(), fault);
}

// The files a reference mesh's load checks (with or without mesh_macrocells.bin), and the
// manifest, whose counts they are checked against.
std::vector<fs::path> Dataset::mesh_files(bool with_macrocells) const {
  std::vector<fs::path> files;
  for (const char* name : {dataset_files::kManifest, dataset_files::kMeshVertices, dataset_files::kMeshElements,
                           dataset_files::kMeshBvhNodes, dataset_files::kMeshBvhItems, dataset_files::kMeshNeighbors})
    files.push_back(dir_ / name);
  if (with_macrocells) files.push_back(dir_ / dataset_files::kMeshMacrocells);
  if (with_macrocells && manifest_.mesh.subcell_masks >= 0) files.push_back(dir_ / dataset_files::kMeshSubcells);
  if (with_macrocells && manifest_.mesh.region_vertices > 0)
    for (const char* name : {dataset_files::kMeshRegionFirst, dataset_files::kMeshRegionVertices})
      files.push_back(dir_ / name);
  return files;
}

void Dataset::count_mesh_bytes() {
  if (is_compact_mesh()) {
    const CompactBytes b = compact_.bytes_by_part();
    mesh_bytes_ = CountedBytes("compact mesh", MemorySpace::host, int64_t(b.total() - b.field));
    return;
  }
  mesh_bytes_ = CountedBytes("mesh", MemorySpace::host,
                             int64_t(mesh_.vertices.size() * sizeof(vec3f) + mesh_.elements.size() * sizeof(UElement) +
                                     mesh_accel_.bvh.nodes.size() * sizeof(ElementBvhNode) +
                                     (mesh_accel_.bvh.items.size() + mesh_accel_.neighbors.size()) * sizeof(uint32_t)));
}

// The compact arrays, each of the manifest's record count (a file the manifest does not list, or
// lists and the table does not know, is a damaged dataset), then checked as a whole.
namespace {
// The manifest's record count of each compact array file, checked to name exactly the arrays.
const std::map<std::string, uint64_t>& compact_records(const DatasetManifest& m, const fs::path& manifest_path) {
  std::map<std::string, uint64_t> unlisted = m.mesh.compact_records;
  CompactMesh names;
  for_each_compact_array(names, [&](const char* file, auto&) {
    if (!unlisted.erase(file)) input_error(manifest_path.string(), std::string("no record count for ") + file);
  });
  if (!unlisted.empty()) input_error(manifest_path.string(), "unknown compact array " + unlisted.begin()->first);
  return m.mesh.compact_records;
}
}  // namespace

void Dataset::load_compact_mesh() {
  const fs::path manifest_path = dir_ / dataset_files::kManifest;
  const std::map<std::string, uint64_t>& records = compact_records(manifest_, manifest_path);
  if (deferred_) return load_compact_index();
  const Stopwatch watch;
  std::vector<fs::path> files{manifest_path};
  for_each_compact_array(compact_, [&](const char* file, auto& array) {
    array = map_topology<typename std::decay_t<decltype(array)>::value_type>(dir_ / file, records.at(file));
    files.push_back(dir_ / file);
  });
  if (compact_.vertices.size() != manifest_.mesh.local_vertices)
    input_error(manifest_path.string(), "local_vertices does not match compact_vertices.bin");
  compact_.elements = manifest_.mesh.elements;
  compact_.leaf_parents = uint32_t(manifest_.mesh.leaf_parents);
  compact_.replicated =
      compact_.vertices.size() - std::min<uint64_t>(compact_.vertices.size(), manifest_.mesh.vertices);
  if (manifest_.mesh.macrocells > 0) {
    files.push_back(dir_ / dataset_files::kMeshMacrocells);
    if (manifest_.mesh.subcell_masks >= 0) files.push_back(dir_ / dataset_files::kMeshSubcells);
    read_stored_macrocells();
  }
  count_mesh_bytes();
  // Checked once per version of the files (io/check_stamp.h).
  const CheckStamp stamp("compact mesh", files);
  if (stamp.passed_before()) return launch_times().add("mesh checked before (stamp)", watch.seconds());
  check_compact_mesh(compact_, manifest_.mesh.by_type, dir_);
  if (manifest_.mesh.macrocells == 0 || build_macrocells_on_stored_grid()) stamp.record();
}

// The compact mesh index only: the tree, leaf and sub-mesh records (checked as at a whole read, but for
// what needs the bytes and vertices: restrict_to checks the part's) and the macrocells.
void Dataset::load_compact_index() {
  const std::map<std::string, uint64_t>& records = manifest_.mesh.compact_records;
  compact_.nodes = read_topology<CompactNode>(dir_ / "compact_nodes.bin", records.at("compact_nodes.bin"));
  compact_.leaves = read_topology<CompactLeaf>(dir_ / "compact_leaves.bin", records.at("compact_leaves.bin"));
  compact_.submeshes =
      read_topology<CompactSubmesh>(dir_ / "compact_submeshes.bin", records.at("compact_submeshes.bin"));
  if (records.at("compact_vertices.bin") != manifest_.mesh.local_vertices)
    input_error((dir_ / dataset_files::kManifest).string(), "local_vertices does not match compact_vertices.bin");
  compact_.elements = manifest_.mesh.elements;
  compact_.leaf_parents = uint32_t(manifest_.mesh.leaf_parents);
  check_submeshes(compact_.submeshes, manifest_.mesh.local_vertices, records.at("compact_bytes.bin"), dir_);
  check_leaf_records(compact_, manifest_.mesh.by_type, dir_);
  check_compact_tree(compact_, dir_);
  read_stored_macrocells();
  count_mesh_bytes();
}

// The vertices' bounds and the chunk boxes (finite, ordered), and the macrocells.
void Dataset::load_reference_index() {
  const fs::path path = dir_ / dataset_files::kMeshChunks;
  std::vector<box3f> boxes = read_topology<box3f>(path, 1 + chunk_count(manifest_.mesh.elements));
  for (size_t i = 0; i < boxes.size(); ++i) {
    const box3f& b = boxes[i];
    if (!(b.lower.x <= b.upper.x && b.lower.y <= b.upper.y && b.lower.z <= b.upper.z) ||
        !std::isfinite(b.lower.x + b.lower.y + b.lower.z + b.upper.x + b.upper.y + b.upper.z))
      input_error(path.string(), i == 0 ? std::string("the vertices' bounds are not a finite box")
                                        : "chunk " + std::to_string(i - 1) + " has no finite box");
  }
  vertex_bounds_ = boxes.front();
  chunk_boxes_.assign(boxes.begin() + 1, boxes.end());
  read_stored_macrocells();
}

void Dataset::read_stored_macrocells() {
  const fs::path path = dir_ / dataset_files::kMeshMacrocells;
  const uint64_t count = manifest_.mesh.macrocells;
  const uint64_t size = file_size_checked(path), bytes = sizeof(MacroGrid) + count * sizeof(StoredMacrocell);
  if (size != bytes) throw_size_mismatch(path, size, bytes);
  MacroGrid grid;
  read_exact(path, 0, &grid, sizeof(grid));
  std::vector<StoredMacrocell> cells(count);
  read_exact(path, sizeof(grid), cells.data(), count * sizeof(StoredMacrocell));
  topology_bytes_read_ += bytes;
  stored_cells_ = macrocells_from_stored(grid, cells, manifest_.mesh.elements, path.string());
  if (manifest_.mesh.subcell_masks >= 0) read_stored_subcells();
}

void Dataset::read_stored_subcells() {
  const fs::path path = dir_ / dataset_files::kMeshSubcells;
  const uint64_t regions = manifest_.mesh.macrocells, masks = uint64_t(manifest_.mesh.subcell_masks);
  if (masks > regions) input_error((dir_ / dataset_files::kManifest).string(), "subcell_masks exceeds macrocells");
  const uint64_t index_bytes = regions * sizeof(uint32_t), bytes = index_bytes + masks * sizeof(SubcellMask);
  const uint64_t size = file_size_checked(path);
  if (size != bytes) throw_size_mismatch(path, size, bytes);
  MacroCells::SubcellMasks& s = stored_cells_.subcells;
  s.of_region.resize(regions);
  s.masks.resize(masks);
  read_exact(path, 0, s.of_region.data(), index_bytes);
  read_exact(path, index_bytes, s.masks.data(), bytes - index_bytes);
  topology_bytes_read_ += bytes;
}

// The macrocells of the whole mesh, built on the grid convert stored (one pass over the elements
// instead of two), which must be this mesh's: bounded by its elements' boxes, with their
// non-empty cells. Only the grid is taken from the file: the cells and step widths are the
// mesh's own, so a damaged file cannot hide elements or make a render march tiny steps.
bool Dataset::build_macrocells_on_stored_grid() {
  const std::string file = (dir_ / dataset_files::kMeshMacrocells).string();
  const MacroGrid grid = stored_cells_.grid;
  box3f seen;
  MacroCells built =
      is_compact_mesh() ? build_macrocells(compact_, &grid, &seen) : build_macrocells(mesh_, &grid, &seen);
  input_check(seen.lower == grid.bounds.lower && seen.upper == grid.bounds.upper, file,
              "the macrocell grid's bounds are not the mesh's");
  input_check(built.cell_of_region == stored_cells_.cell_of_region, file,
              "the non-empty macrocells are not the mesh's");
  // Stored masks that miss a subcell some element's box overlaps would make samples in it NaN.
  input_check(stored_cells_.subcells.of_region.empty() || built.subcells == stored_cells_.subcells,
              (dir_ / dataset_files::kMeshSubcells).string(), "the subcell masks are not the mesh's");
  const bool widths_as_stored = built.step_width == stored_cells_.step_width;
  stored_cells_ = std::move(built);
  return widths_as_stored;
}

MeshIndex Dataset::mesh_index() const {
  if (!is_mesh() || part()) throw std::logic_error("Dataset::mesh_index: not a mesh, or already restricted");
  if (is_compact_mesh()) return compact_mesh_index(compact_, deferred_ ? stored_cells_ : build_macrocells(compact_));
  if (deferred_) return reference_mesh_index(chunk_boxes_, manifest_.mesh.elements, stored_cells_);
  return reference_mesh_index(reference_chunk_boxes(mesh_, mesh_accel_.bvh.items), mesh_.elements.size(),
                              build_macrocells(mesh_));
}

Box3<double> Dataset::mesh_world_bounds() const {
  if (!deferred_) return world_bounds(mesh_vertices(), manifest_.transform);
  // Every local vertex of a compact mesh is a corner of an element, so the grid's bounds are the
  // vertices'; the reference encoding stores them (a vertex of no element counts).
  const box3f& b = is_compact_mesh() ? stored_cells_.grid.bounds : vertex_bounds_;
  return {manifest_.transform.to_world(vec3d(b.lower)), manifest_.transform.to_world(vec3d(b.upper))};
}

const UMesh& Dataset::mesh() const {
  if (is_compact_mesh()) throw std::logic_error("Dataset::mesh: the dataset stores the compact encoding");
  if (deferred_) throw std::logic_error("Dataset::mesh: the topology is deferred (restrict_to first)");
  return mesh_;
}

const MeshAccel& Dataset::mesh_accel() const {
  if (is_compact_mesh()) throw std::logic_error("Dataset::mesh_accel: the dataset stores the compact encoding");
  return mesh_accel_;
}

const MacroCells* Dataset::macrocells() const {
  return is_mesh() && !restricted_ && manifest_.mesh.macrocells > 0 ? &stored_cells_ : nullptr;
}

const RegionVertices* Dataset::region_vertices() const {
  return is_mesh() && !restricted_ && stored_region_vertices_ ? &*stored_region_vertices_ : nullptr;
}

const CompactMesh& Dataset::compact_mesh() const {
  if (!is_compact_mesh()) throw std::logic_error("Dataset::compact_mesh: the dataset stores no compact encoding");
  if (deferred_) throw std::logic_error("Dataset::compact_mesh: the topology is deferred (restrict_to first)");
  return compact_;
}

std::vector<Cell> Dataset::load_cells() const {
  return read_records<Cell>(dir_ / dataset_files::kCells, manifest_.cell_count);
}

fs::path Dataset::values_path(int field, int step) const {
  return dir_ / dataset_files::field_values(manifest_.fields.at(size_t(field)), step);
}

fs::path Dataset::file_order_values_path(int field, int step) const {
  return dir_ / dataset_files::field_file_order_values(manifest_.fields.at(size_t(field)), step);
}

std::vector<uint32_t> Dataset::load_file_index() const {
  const fs::path path = dir_ / dataset_files::kFileIndex;
  if (!manifest_.file_order)
    input_error(path.string(), "the dataset has no file-order copies (convert with --file-order)");
  std::vector<uint32_t> index = read_records<uint32_t>(path, manifest_.cell_count);
  std::vector<bool> seen(index.size(), false);
  for (size_t i = 0; i < index.size(); ++i) {
    const uint32_t k = index[i];
    if (k >= index.size() || seen[k])
      input_error(path.string(), "not a permutation: entry " + std::to_string(i) + " is " + std::to_string(k) +
                                     (k >= index.size() ? " (out of range)" : " (repeated)"));
    seen[k] = true;
  }
  return index;
}

std::vector<float> Dataset::load_file_order_values(int field, int step) const {
  return read_records<float>(file_order_values_path(field, step), manifest_.value_count(), kFileAlignment);
}

std::vector<BvhNode> Dataset::read_abr_bvh_tree() const {
  const fs::path path = dir_ / dataset_files::kAbrBvh;
  const std::vector<uint32_t> links = read_records<uint32_t>(path, 2 * manifest_.abr_bvh_node_count);
  std::vector<BvhNode> nodes;
  nodes.reserve(manifest_.abr_bvh_node_count);
  for (size_t i = 0; i < manifest_.abr_bvh_node_count; ++i)
    nodes.push_back({box3f::make_empty(), links[2 * i], links[2 * i + 1]});
  if (const std::string problem = bvh_tree_problem(nodes, manifest_.abr_count); !problem.empty())
    input_error(path.string(), "bad ABR BVH: " + problem);
  return nodes;
}

void Dataset::count_topology_bytes() {
  brick_bytes_ = CountedBytes("bricks", MemorySpace::host, int64_t(topology_.bricks.size() * sizeof(Brick)));
  abr_bytes_ = CountedBytes("ABRs", MemorySpace::host, int64_t(topology_.abrs.size() * sizeof(Abr)));
  abr_list_bytes_ =
      CountedBytes("ABR brick lists", MemorySpace::host, int64_t(topology_.abr_bricks.size() * sizeof(uint32_t)));
}

std::vector<float> Dataset::load_values(int field, int step) const {
  const fs::path path = values_path(field, step);
  if (!part()) {
    std::vector<float> all = read_records<float>(path, manifest_.value_count(), kFileAlignment);
    value_bytes_read_ += all.size() * sizeof(float);
    return all;
  }
  // The whole file is checked as load_values checks it; only the part's runs are read.
  const uint64_t size = file_size_checked(path), bytes = manifest_.value_count() * sizeof(float);
  if (size < bytes || size - bytes >= kFileAlignment) throw_size_mismatch(path, size, bytes);
  uint64_t count = 0;
  for (const ByteRun& run : part_runs_) count += run.bytes / sizeof(float);
  std::vector<float> values(count);
  read_runs(path, part_runs_, values.data());
  value_bytes_read_ += count * sizeof(float);
  return values;
}

std::vector<Range> Dataset::load_abr_ranges(int field, int step) const {
  std::vector<Range> all = read_records<Range>(
      dir_ / dataset_files::field_ranges(manifest_.fields.at(size_t(field)), step), manifest_.abr_count);
  if (!part()) return all;
  std::vector<Range> mine;
  mine.reserve(part_.abrs.size());
  for (uint32_t a : part_.abrs) mine.push_back(all[a]);
  return mine;
}

namespace {
// Appends a run of bytes, joining it to the last when they are contiguous.
void append_run(std::vector<ByteRun>& runs, const ByteRun& run) {
  if (!runs.empty() && runs.back().offset + runs.back().bytes == run.offset)
    runs.back().bytes += run.bytes;
  else
    runs.push_back(run);
}
}  // namespace

void Dataset::restrict_to(DatasetPart part) {
  if (this->part()) throw UsageError("the dataset is already restricted to a part");
  part_runs_.clear();
  if (is_mesh())
    restrict_mesh(part.mesh_items);
  else
    restrict_bricks(part);
  part_ = std::move(part);
  restricted_ = true;
}

uint32_t Dataset::local_abr(uint32_t global) const {
  if (!abr_subset_) return global;  // all ABRs were read
  const auto it = std::lower_bound(abr_ids_.begin(), abr_ids_.end(), global);
  if (it == abr_ids_.end() || *it != global)
    throw std::logic_error("Dataset::restrict_to: ABR " + std::to_string(global) + " was not read (read_abr_chunks)");
  return uint32_t(it - abr_ids_.begin());
}

void Dataset::restrict_bricks(const DatasetPart& part) {
  if (deferred_) throw std::logic_error("Dataset::restrict_to: the ABRs are deferred (read_abr_chunks first)");
  AmrTopology local;
  std::vector<uint32_t> local_index(topology_.bricks.size(), UINT32_MAX);
  uint64_t offset = 0;
  for (uint32_t g : part.bricks) {
    Brick b = topology_.bricks.at(g);
    const uint64_t count = uint64_t(b.cell_count());
    // Bricks are contiguous in the file (device order): neighbours join one run.
    append_run(part_runs_, {b.value_offset * sizeof(float), count * sizeof(float)});
    b.value_offset = offset;
    offset += count;
    local_index[g] = uint32_t(local.bricks.size());
    local.bricks.push_back(b);
  }
  for (uint32_t g : part.abrs) {
    Abr a = topology_.abrs.at(local_abr(g));
    const uint32_t first = uint32_t(local.abr_bricks.size());
    for (uint32_t k = 0; k < a.brick_count; ++k) {
      const uint32_t l = local_index[topology_.abr_bricks[a.first_brick + k]];
      if (l == UINT32_MAX) throw UsageError("a part's ABR uses a brick outside the part");
      local.abr_bricks.push_back(l);  // same order: the tent sums add up in the same order
    }
    a.first_brick = first;
    local.abrs.push_back(a);
  }
  local.cell_count = offset;
  topology_ = std::move(local);
  abr_ids_.clear();  // the part's ABRs are numbered in its order now
  abr_subset_ = false;
  count_topology_bytes();
}

// The part's vertices are in ascending order of the file's: their values are runs of it.
void Dataset::restrict_mesh(const std::vector<uint32_t>& items) {
  stored_region_vertices_.reset();  // the whole mesh's: a part builds its own macrocells
  std::vector<uint32_t> source;
  if (is_compact_mesh()) {
    if (deferred_)
      read_compact_part(items, source);
    else
      compact_ = compact_subset(compact_, items, source);
  } else {
    if (deferred_)
      read_reference_part(items, source);
    else
      mesh_ = mesh_subset(mesh_, chunk_elements(items, mesh_accel_.bvh.items), source);
    mesh_accel_ = mesh_.elements.empty() ? MeshAccel{} : build_mesh_accel(mesh_);
  }
  deferred_ = false;
  count_mesh_bytes();
  for (uint32_t v : source) append_run(part_runs_, {uint64_t(v) * sizeof(float), sizeof(float)});
}

namespace {
// A file of exactly `count` records of `record` bytes (as read_records checks it), of which only
// runs are read.
void check_record_file(const fs::path& path, uint64_t count, uint64_t record) {
  const uint64_t size = file_size_checked(path);
  if (size != count * record) throw_size_mismatch(path, size, count * record);
}
}  // namespace

// The chunks' items, then the elements they name and the vertices those use, each as runs of the
// files, checked before they are used as at a whole read (items distinct elements, elements'
// slots, finite vertices), and each element inside the box its chunk was chosen by.
void Dataset::read_reference_part(const std::vector<uint32_t>& chunks, std::vector<uint32_t>& source_vertex) {
  const fs::path items_path = dir_ / dataset_files::kMeshBvhItems, elements_path = dir_ / dataset_files::kMeshElements,
                 vertices_path = dir_ / dataset_files::kMeshVertices;
  const uint64_t elements = manifest_.mesh.elements, vertex_count = manifest_.mesh.vertices;
  check_record_file(items_path, elements, sizeof(uint32_t));
  check_record_file(elements_path, elements, sizeof(UElement));
  check_record_file(vertices_path, vertex_count, sizeof(vec3f));
  std::vector<ByteRun> runs;
  std::vector<uint32_t> chunk_of;  // of each item read
  for (uint32_t c : chunks) {
    append_run(runs, {chunk_first(c) * sizeof(uint32_t), chunk_size(c, elements) * sizeof(uint32_t)});
    chunk_of.insert(chunk_of.end(), chunk_size(c, elements), c);
  }
  std::vector<uint32_t> items(chunk_of.size());
  read_runs(items_path, runs, items.data());
  topology_bytes_read_ += items.size() * sizeof(uint32_t);
  std::vector<std::pair<uint32_t, uint32_t>> held;  // (element, chunk), by element
  for (size_t i = 0; i < items.size(); ++i) {
    if (items[i] >= elements) input_error(items_path.string(), "BVH items are not a permutation of the elements");
    held.push_back({items[i], chunk_of[i]});
  }
  std::sort(held.begin(), held.end());
  runs.clear();
  for (size_t i = 0; i < held.size(); ++i) {
    if (i > 0 && held[i].first == held[i - 1].first)
      input_error(items_path.string(), "BVH items are not a permutation of the elements");
    append_run(runs, {uint64_t(held[i].first) * sizeof(UElement), sizeof(UElement)});
  }
  std::vector<UElement> records(held.size());
  read_runs(elements_path, runs, records.data());
  topology_bytes_read_ += records.size() * sizeof(UElement);
  for (size_t i = 0; i < held.size(); ++i)
    if (!element_valid(records[i], vertex_count))
      input_error(elements_path.string(), "element " + std::to_string(held[i].first) + " is invalid");
  mesh_ = mesh_part(std::move(records), source_vertex);
  runs.clear();
  for (uint32_t v : source_vertex) append_run(runs, {uint64_t(v) * sizeof(vec3f), sizeof(vec3f)});
  mesh_.vertices.resize(source_vertex.size());
  read_runs(vertices_path, runs, mesh_.vertices.data());
  topology_bytes_read_ += mesh_.vertices.size() * sizeof(vec3f);
  check_finite_vertices(mesh_.vertices, vertices_path.string());
  for (size_t i = 0; i < held.size(); ++i)
    if (!chunk_boxes_[held[i].second].contains(element_box(mesh_.vertices.data(), mesh_.elements[i])))
      input_error((dir_ / dataset_files::kMeshChunks).string(),
                  "element " + std::to_string(held[i].first) + " lies outside its chunk's box");
}

// The leaves' bytes and then the vertices their tables name, each as runs of the files (leaves
// and vertices ascend), checked before they are used as at a whole read; then the part as a whole
// (check_compact_mesh), and each leaf inside the index box it was chosen by.
void Dataset::read_compact_part(const std::vector<uint32_t>& leaves, std::vector<uint32_t>& source_vertex) {
  const fs::path bytes_path = dir_ / "compact_bytes.bin", vertices_path = dir_ / "compact_vertices.bin";
  const uint64_t vertex_count = manifest_.mesh.local_vertices;
  const uint64_t byte_count = manifest_.mesh.compact_records.at("compact_bytes.bin");
  check_record_file(bytes_path, byte_count, 1);
  check_record_file(vertices_path, vertex_count, sizeof(vec3f));
  std::vector<ByteRun> runs;
  std::vector<uint64_t> offsets;  // of each leaf's bytes in `bytes`
  uint64_t total = 0;
  for (uint32_t l : leaves) {
    const CompactLeaf& leaf = compact_.leaves.at(l);
    const SubmeshRuns in = submesh_runs(compact_.submeshes, leaf.submesh, vertex_count, byte_count);
    const uint64_t begin = in.bytes_begin + leaf.first_byte, size = leaf_byte_count(leaf);
    if (begin + size > in.bytes_end)
      input_error((dir_ / "compact_leaves.bin").string(),
                  "leaf " + std::to_string(l) + " has bytes beyond its sub-mesh's");
    append_run(runs, {begin, size});
    offsets.push_back(total);
    total += size;
  }
  std::vector<uint8_t> bytes(total);
  read_runs(bytes_path, runs, bytes.data());
  topology_bytes_read_ += total;
  CompactPieces pieces;
  for (size_t i = 0; i < leaves.size(); ++i) {
    const CompactLeaf& leaf = compact_.leaves[leaves[i]];
    const uint64_t submesh_vertices = submesh_runs(compact_.submeshes, leaf.submesh, vertex_count, byte_count).vertices;
    if (const std::string problem = leaf_bytes_problem(leaf, bytes.data() + offsets[i], submesh_vertices);
        !problem.empty())
      input_error(bytes_path.string(), "leaf " + std::to_string(leaves[i]) + " " + problem);
    pieces.leaves.push_back(leaf);
    pieces.bytes.push_back(bytes.data() + offsets[i]);
  }
  const MeshIndex index = mesh_index();  // before compact_ is replaced
  CompactMesh part = compact_part(pieces, compact_.submeshes, source_vertex);
  runs.clear();
  for (uint32_t v : source_vertex) append_run(runs, {uint64_t(v) * sizeof(vec3f), sizeof(vec3f)});
  std::vector<vec3f> vertices(source_vertex.size());
  read_runs(vertices_path, runs, vertices.data());
  topology_bytes_read_ += vertices.size() * sizeof(vec3f);
  check_finite_vertices(vertices, vertices_path.string());  // before the part's tree quantizes boxes
  const std::vector<box3f> boxes = finish_compact_part(part, std::move(vertices));
  uint64_t by_type[4] = {};
  for (size_t i = 0; i < leaves.size(); ++i) {
    for (int t = 0; t < 4; ++t) by_type[t] += part.leaves[i].counts[t];
    if (!index.item_boxes[leaves[i]].contains(boxes[i]))
      input_error((dir_ / "compact_nodes.bin").string(), "leaf " + std::to_string(leaves[i]) + " lies outside its box");
  }
  if (!leaves.empty()) check_compact_mesh(part, by_type, dir_);
  compact_ = std::move(part);
}

// The chunks' ABRs, then their brick lists, each as runs of the files, checked as at a whole read
// (validate_abrs); each ABR must lie within the box and width its chunk was chosen by.
void Dataset::read_abr_chunks(const std::vector<uint32_t>& chunks) {
  if (!deferred_ || is_mesh()) throw std::logic_error("Dataset::read_abr_chunks: the ABRs are not deferred");
  read_chunk_abrs(chunks);
  read_abr_lists();
  validate_abrs(topology_, (dir_ / dataset_files::kBricks).string(), abr_ids_);
  check_abrs_in_chunks();
  deferred_ = false;
  count_topology_bytes();
}

void Dataset::read_chunk_abrs(const std::vector<uint32_t>& chunks) {
  const fs::path path = dir_ / dataset_files::kAbrs;
  check_record_file(path, manifest_.abr_count, sizeof(Abr));
  std::vector<ByteRun> runs;
  for (uint32_t c : chunks) {
    if (c >= stored_abr_chunks_.size() || (!abr_ids_.empty() && chunk_first(c) <= abr_ids_.back()))
      throw std::logic_error("Dataset::read_abr_chunks: chunks out of range or not ascending");
    const uint32_t size = chunk_size(c, manifest_.abr_count);
    append_run(runs, {chunk_first(c) * sizeof(Abr), size * sizeof(Abr)});
    for (uint32_t k = 0; k < size; ++k) abr_ids_.push_back(uint32_t(chunk_first(c) + k));
  }
  topology_.abrs.resize(abr_ids_.size());
  read_runs(path, runs, topology_.abrs.data());
  topology_bytes_read_ += topology_.abrs.size() * sizeof(Abr);
  abr_subset_ = true;
}

// The lists of the ABRs read, rebased onto the lists read. They must follow one another in ABR
// order, as convert writes them, so that what is read is at most the file.
void Dataset::read_abr_lists() {
  std::vector<ByteRun> runs;
  uint64_t end = 0, local = 0;  // of the last list in the file; of the lists read
  for (size_t i = 0; i < topology_.abrs.size(); ++i) {
    Abr& a = topology_.abrs[i];
    if (a.first_brick < end || uint64_t(a.first_brick) + a.brick_count > manifest_.abr_brick_count)
      input_error((dir_ / dataset_files::kAbrs).string(),
                  "ABR " + std::to_string(abr_ids_[i]) + "'s brick list is out of order or range");
    end = uint64_t(a.first_brick) + a.brick_count;
    append_run(runs, {uint64_t(a.first_brick) * sizeof(uint32_t), uint64_t(a.brick_count) * sizeof(uint32_t)});
    a.first_brick = uint32_t(local);
    local += a.brick_count;
  }
  const fs::path path = dir_ / dataset_files::kAbrBricks;
  check_record_file(path, manifest_.abr_brick_count, sizeof(uint32_t));
  topology_.abr_bricks.resize(local);
  read_runs(path, runs, topology_.abr_bricks.data());
  topology_bytes_read_ += local * sizeof(uint32_t);
}

// A rank chose the chunks by their boxes and widths: an ABR beyond them would be missed by the
// ranks that need it.
void Dataset::check_abrs_in_chunks() const {
  for (size_t i = 0; i < topology_.abrs.size(); ++i) {
    const Abr& a = topology_.abrs[i];
    const AbrChunk& c = stored_abr_chunks_[abr_ids_[i] / kIndexChunk];
    if (!c.box.contains(a.box) || !(a.finest_width <= c.finest_width))
      input_error((dir_ / dataset_files::kAbrChunks).string(),
                  "ABR " + std::to_string(abr_ids_[i]) + " lies outside its chunk's box or width");
  }
}

// ---------------------------------------------------------------------------------------------
namespace {
std::vector<LevelInfo> count_levels(const std::vector<Brick>& bricks) {
  std::vector<uint64_t> counts(kMaxLevel + 1, 0);
  for (const Brick& b : bricks) counts[size_t(b.level)] += uint64_t(b.cell_count());
  std::vector<LevelInfo> levels;
  for (int l = 0; l <= kMaxLevel; ++l)
    if (counts[size_t(l)]) levels.push_back({l, counts[size_t(l)]});
  return levels;
}

box3i grid_bounds(const std::vector<Brick>& bricks) {
  box3i b = box3i::make_empty();
  for (const Brick& br : bricks) b.extend(br.cell_box());
  return b;
}
}  // namespace

namespace {
// Source field indices for the names asked for (all fields when none are).
std::vector<int> selected_fields(const AmrSource& source, const std::vector<std::string>& wanted) {
  const std::vector<std::string> names = source.field_names();
  std::vector<int> fields;
  if (wanted.empty())
    for (size_t f = 0; f < names.size(); ++f) fields.push_back(int(f));
  for (const std::string& w : wanted) {
    const auto it = std::find(names.begin(), names.end(), w);
    if (it == names.end()) input_error(source.origin(), "no field '" + w + "' (--fields)");
    fields.push_back(int(it - names.begin()));
  }
  return fields;
}
}  // namespace

void check_free_space(const fs::path& out, uint64_t cells, uint64_t values_per_cell, bool file_order) {
  const uint64_t bytes = cells * (sizeof(Cell) + sizeof(Brick) / 8 + (file_order ? 4 : 0)) +
                         cells * values_per_cell * 4 + (uint64_t(1) << 20);
  std::error_code ec;
  const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
  const fs::space_info space = fs::space(dir, ec);
  if (ec || bytes <= space.available) return;
  char text[160];
  std::snprintf(text, sizeof(text), "needs about %.2f GB of disk, only %.2f GB free", double(bytes) * 1e-9,
                double(space.available) * 1e-9);
  input_error(out.string(), text);
}

void check_field_values(const std::vector<float>& v, const std::string& origin, const std::string& field, int step) {
  std::atomic<uint64_t> first_inf{UINT64_MAX};
  parallel_for_ranges(
      int64_t(v.size()),
      [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i)
          if (std::isinf(v[size_t(i)])) {
            uint64_t cur = first_inf.load();
            while (uint64_t(i) < cur && !first_inf.compare_exchange_weak(cur, uint64_t(i))) {
            }
            return;
          }
      },
      1 << 16);
  const std::string where = "field '" + field + "' step " + std::to_string(step) + ": ";
  if (first_inf.load() != UINT64_MAX)
    input_error(origin, where + "value " + std::to_string(first_inf.load()) +
                            " is infinite or beyond float32 range (|v| > 3.4e38); use NaN for no data");
  const Range r = value_range(v.data(), v.size());
  if (!(r.lo <= r.hi)) input_error(origin, where + "no finite value (every value is NaN)");
}

ConvertStats convert_to_dataset(AmrSource& source, const fs::path& target_dir, const ConvertOptions& options) {
  ConvertStats stats;
  Stopwatch watch;
  const std::string origin = source.origin();
  // file_index.bin holds uint32 positions (as does the brick builder's input index).
  if (options.file_order && source.cell_count() > uint64_t(UINT32_MAX))
    input_error(target_dir.string(), "--file-order: " + std::to_string(source.cell_count()) +
                                         " cells; the file index holds 32-bit positions, so at most 2^32 - 1 cells");
  if (const std::string problem = transform_problem(source.transform()); !problem.empty()) input_error(origin, problem);
  // Built beside the target and swapped in at the end: all or nothing, also over an old dataset.
  StagedDirectory staged(target_dir, dataset_files::kManifest);
  const fs::path& out_dir = staged.path();
  const uint64_t values_per_cell = uint64_t(source.step_count()) *
                                   (options.fields.empty() ? source.field_names().size() : options.fields.size()) *
                                   (options.file_order ? 2 : 1);
  check_free_space(target_dir, source.cell_count(), values_per_cell, options.file_order);
  std::vector<Cell> cells = source.take_cells();
  if (cells.empty()) input_error(origin, "no cells");
  stats.cells_seconds = watch.seconds();

  watch.lap();
  BrickBuildResult built = build_bricks(std::move(cells), origin);
  AmrTopology topology;
  topology.cell_count = built.device_cells.size();
  topology.bricks = std::move(built.bricks);
  stats.bricks_seconds = watch.seconds();

  watch.lap();
  build_abrs(topology, origin);
  stats.abrs_seconds = watch.seconds();
  stats.topology_bytes = topology.bricks.size() * sizeof(Brick) + topology.abrs.size() * sizeof(Abr) +
                         topology.abr_bricks.size() * sizeof(uint32_t);

  DatasetManifest manifest;
  manifest.source = source.description();
  manifest.transform = source.transform();
  manifest.grid_bounds = grid_bounds(topology.bricks);
  manifest.levels = count_levels(topology.bricks);
  for (int s = 0; s < source.step_count(); ++s) manifest.step_times.push_back(source.step_time(s));
  const std::vector<int> fields = selected_fields(source, options.fields);
  std::vector<std::string> field_names;
  for (int f : fields) field_names.push_back(source.field_names()[size_t(f)]);
  DatasetWriter writer(out_dir, manifest, field_names);
  writer.write_topology(topology, built.device_cells);
  std::vector<Cell>().swap(built.device_cells);
  // Reading file order back into device order is out[i] = in[input_index[i]]: the input index is
  // the file index.
  if (options.file_order) writer.write_file_index(built.input_index);

  watch.lap();
  const uint64_t n = topology.cell_count;
  std::vector<float> input(n), device(n);
  const int steps = source.step_count();
  Progress progress("converting", uint64_t(steps) * field_names.size(), !options.quiet);
  for (int step = 0; step < steps; ++step) {
    for (size_t field = 0; field < field_names.size(); ++field) {
      progress.set_detail(field_names[field] + " step " + std::to_string(step));
      source.read_values(fields[field], step, input.data());
      check_field_values(input, origin, field_names[field], step);
      if (options.file_order) writer.write_file_order_values(int(field), step, input.data(), n);
      const uint32_t* index = built.input_index.data();
      parallel_for("reorder", int64_t(n), [&](int64_t i) { device[size_t(i)] = input[index[i]]; });
      writer.write_values(int(field), step, device);
      progress.advance();
    }
  }
  progress.finish();
  stats.values_seconds = watch.seconds();
  writer.finish();
  staged.commit();
  return stats;
}

}  // namespace vs
