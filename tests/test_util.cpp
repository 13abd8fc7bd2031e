#include "test_util.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "volstream/core/error.h"

namespace vs::test {
std::filesystem::path scratch_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string unique = name;
  if (info) unique = std::string(info->test_suite_name()) + "." + info->name() + "." + name;
  auto dir = std::filesystem::temp_directory_path() / "volstream_tests" / unique;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary) << bytes;
}

std::filesystem::path damaged_copy(const std::filesystem::path& from, const std::string& name, const std::string& file,
                                   const std::function<void(std::vector<char>&)>& damage) {
  namespace fs = std::filesystem;
  const fs::path dir = scratch_dir(name);
  fs::copy(from, dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  std::vector<char> bytes;
  {
    std::ifstream in(dir / file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  damage(bytes);
  std::ofstream(dir / file, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
  return dir;
}

std::string input_error_line(const std::function<void()>& open) {
  try {
    open();
  } catch (const InputError& e) {
    const std::string line = e.file() + ": " + e.what();
    EXPECT_EQ(line.find('\n'), std::string::npos) << line;
    return line;
  }
  return "accepted";
}
}  // namespace vs::test

#include <algorithm>
#include <cmath>
#include <random>

namespace vs::test {

namespace {
void refine_cell(const Cell& c, std::mt19937& rng, double refine, std::vector<Cell>& out) {
  std::uniform_real_distribution<double> u(0, 1);
  if (c.level == 0 || u(rng) >= refine) {
    out.push_back(c);
    return;
  }
  const int32_t half = level_width(c.level - 1);
  for (int k = 0; k < 8; ++k) {
    const vec3i off(k & 1 ? half : 0, k & 2 ? half : 0, k & 4 ? half : 0);
    refine_cell({c.lower + off, c.level - 1}, rng, refine, out);
  }
}
}  // namespace

std::vector<Cell> random_octree_cells(uint32_t seed, vec3i root_dims, int levels, double refine) {
  std::mt19937 rng(seed);
  std::vector<Cell> out;
  const int32_t w = level_width(levels - 1);
  for (int z = 0; z < root_dims.z; ++z)
    for (int y = 0; y < root_dims.y; ++y)
      for (int x = 0; x < root_dims.x; ++x) refine_cell({vec3i(x, y, z) * w, levels - 1}, rng, refine, out);
  std::shuffle(out.begin(), out.end(), rng);
  return out;
}

float test_value(const Cell& c, int variant) {
  const float w = float(level_width(c.level));
  const vec3f p = vec3f(c.lower) + vec3f(0.5f * w);
  return 1.5f + 0.4f * std::sin(0.21f * p.x + variant) * std::cos(0.13f * p.y) + 0.02f * float(c.level) +
         0.05f * std::sin(0.37f * p.z);
}

}  // namespace vs::test

#include "volstream/amr/abrs.h"
#include "volstream/amr/bricks.h"
#include "volstream/amr/ranges.h"

namespace vs::test {

TestVolume make_test_volume(std::vector<Cell> cells, const GridFunction& f, const WorldTransform& xf) {
  TestVolume v;
  BrickBuildResult r = build_bricks(std::move(cells), "test");
  v.topology.bricks = r.bricks;
  v.topology.cell_count = r.device_cells.size();
  build_abrs(v.topology, "test");
  v.values.resize(r.device_cells.size());
  for (size_t i = 0; i < r.device_cells.size(); ++i) {
    const Cell& c = r.device_cells[i];
    v.values[i] = float(f(vec3d(c.lower) + vec3d(0.5 * level_width(c.level))));
  }
  v.abr_ranges = compute_abr_ranges(v.topology, v.values.data());
  v.transform = xf;
  return v;
}

std::vector<float> test_values(const TestVolume& v, const GridFunction& f) {
  // Cells in device order, from the bricks.
  std::vector<float> out(v.values.size());
  for (const Brick& b : v.topology.bricks)
    for (int32_t z = 0; z < b.dims.z; ++z)
      for (int32_t y = 0; y < b.dims.y; ++y)
        for (int32_t x = 0; x < b.dims.x; ++x) {
          const vec3d centre = vec3d(b.lower) + (vec3d(x, y, z) + vec3d(0.5)) * double(b.width());
          out[b.value_offset + (uint64_t(z) * b.dims.y + y) * b.dims.x + x] = float(f(centre));
        }
  return out;
}

std::vector<Cell> uniform_cells(vec3i dims, int level, vec3i offset) {
  std::vector<Cell> cells;
  const int32_t w = level_width(level);
  for (int z = 0; z < dims.z; ++z)
    for (int y = 0; y < dims.y; ++y)
      for (int x = 0; x < dims.x; ++x) cells.push_back({offset + vec3i(x, y, z) * w, level});
  return cells;
}

std::string bvh_difference(const std::vector<BvhNode>& a, const std::vector<BvhNode>& b) {
  if (a.size() != b.size()) return std::to_string(a.size()) + " vs " + std::to_string(b.size()) + " nodes";
  for (size_t i = 0; i < a.size(); ++i)
    if (!(a[i].index == b[i].index && a[i].is_leaf == b[i].is_leaf && a[i].box.lower == b[i].box.lower &&
          a[i].box.upper == b[i].box.upper))
      return "node " + std::to_string(i);
  return "";
}

}  // namespace vs::test

namespace vs::test {
std::vector<vec3f> points_around(std::span<const vec3f> vertices, int count, uint32_t seed) {
  box3f b = box3f::make_empty();
  for (const vec3f& v : vertices) b.extend(v);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-0.05f, 1.05f);
  std::vector<vec3f> points(static_cast<size_t>(count));
  for (vec3f& p : points) p = b.lower + b.size() * vec3f(u(rng), u(rng), u(rng));
  return points;
}
}  // namespace vs::test

#include "volstream/render/integrators/umesh_renderer.h"
#include "volstream/umesh/demo.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs::test {
DemoMesh demo_mesh(const std::string& name, uint64_t elements) {
  DemoMesh d;
  d.data = make_mesh_demo({name, elements, 1}, 0);
  d.transform = mesh_transform(d.data);
  d.mesh = make_umesh(d.data, d.transform, name);
  const auto fields = mesh_fields(d.data);
  d.density = mesh_field_values(d.data, fields[0]);
  d.linear = mesh_field_values(d.data, fields[1]);
  return d;
}

std::vector<float> mesh_field(const MeshData& m, const std::string& name) {
  for (const MeshFieldRef& f : mesh_fields(m))
    if (f.name == name) return mesh_field_values(m, f);
  throw std::runtime_error("no field " + name);
}

const MeshArray& array_named(const std::vector<MeshArray>& arrays, const std::string& name) {
  for (const MeshArray& a : arrays)
    if (a.name == name) return a;
  throw std::runtime_error("no array " + name);
}

int expect_probe_is_brute_force(const UMesh& mesh, const WorldTransform& transform, const float* values,
                                const std::vector<vec3f>& points) {
  const UMeshRenderer renderer(mesh, transform);
  const std::vector<float> fast = renderer.probe(values, points);
  const std::vector<double> reference = probe_brute_force(mesh, values, points);
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(std::isnan(fast[i]), std::isnan(reference[i])) << "point " << i;
    if (std::isnan(fast[i]) || std::isnan(reference[i])) continue;
    ++inside;
    EXPECT_NEAR(fast[i], reference[i], 1e-5 * std::max(1.0, std::fabs(reference[i]))) << "point " << i;
  }
  return inside;
}

void expect_probes_alike(const MeshData& mesh_a, const std::string& a_field, const MeshData& mesh_b,
                         const std::string& b_field, bool (*compared)(const vec3d&)) {
  const WorldTransform xf = mesh_transform(mesh_a);
  const UMesh a = make_umesh(mesh_a, xf, "a"), b = make_umesh(mesh_b, xf, "b");
  std::vector<vec3f> points = points_around(b.vertices, 4000, 5);
  if (compared) std::erase_if(points, [&](const vec3f& p) { return !compared(xf.to_world(vec3d(p))); });
  const std::vector<float> fa = mesh_field(mesh_a, a_field), fb = mesh_field(mesh_b, b_field);
  const std::vector<float> pa = UMeshRenderer(a, xf).probe(fa.data(), points),
                           pb = UMeshRenderer(b, xf).probe(fb.data(), points);
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(std::isnan(pa[i]), std::isnan(pb[i])) << "point " << i;
    if (std::isnan(pa[i])) continue;
    ++inside;
    EXPECT_NEAR(pa[i], pb[i], 1e-5 * std::max(1.0f, std::fabs(pa[i]))) << "point " << i;
  }
  EXPECT_GT(inside, int(points.size()) / 8);
}

}  // namespace vs::test
