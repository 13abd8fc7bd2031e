// Helpers shared by the tests.
#pragma once
#include <filesystem>
#include <string>

namespace vs::test {
// A fresh empty directory under the build tree's temp area, unique per test.
std::filesystem::path scratch_dir(const std::string& name);
// A whole file's bytes ("" for a missing one), and a file written with exactly `bytes`.
std::string file_bytes(const std::filesystem::path& file);
void write_bytes(const std::filesystem::path& file, const std::string& bytes);
}  // namespace vs::test

#include <functional>
#include <span>
#include <vector>

namespace vs::test {
// A scratch copy (scratch_dir(name)) of the dataset in `from` with its `file` changed by `damage`.
std::filesystem::path damaged_copy(const std::filesystem::path& from, const std::string& name, const std::string& file,
                                   const std::function<void(std::vector<char>&)>& damage);
// Runs `open`: the InputError it throws as one line "file: message" (checked to be one line), or
// "accepted" when it throws none.
std::string input_error_line(const std::function<void()>& open);
}  // namespace vs::test

#include <cstdint>
#include <vector>

#include "volstream/amr/model.h"

namespace vs::test {
// Octree leaves: a root grid of cells at level `levels-1`, each refined into 8 children with
// probability `refine` (per level), deterministic for a seed. Cells come out shuffled.
std::vector<Cell> random_octree_cells(uint32_t seed, vec3i root_dims, int levels, double refine);
// A smooth test function of grid position (plus a per-cell jitter that makes level jumps visible).
float test_value(const Cell& c, int variant = 0);
// Empty when the two trees are the same node for node (links and boxes), else the first
// difference.
std::string bvh_difference(const std::vector<BvhNode>& a, const std::vector<BvhNode>& b);
}  // namespace vs::test

#include <functional>

#include "volstream/amr/source.h"

namespace vs::test {
// A topology built from cells (bricks, ABRs), values from a function of the cell centre (grid
// units) in device order, and the ABR ranges of those values.
struct TestVolume {
  AmrTopology topology;
  std::vector<float> values;  // device order
  std::vector<Range> abr_ranges;
  WorldTransform transform;
};
using GridFunction = std::function<double(const vec3d& centre)>;
TestVolume make_test_volume(std::vector<Cell> cells, const GridFunction& f, const WorldTransform& xf = {});
// Values of another function on the same volume's cells (device order).
std::vector<float> test_values(const TestVolume& volume, const GridFunction& f);
// dims cells of one level, x fastest, starting at `offset` (grid units).
std::vector<Cell> uniform_cells(vec3i dims, int level = 0, vec3i offset = {0, 0, 0});
}  // namespace vs::test

#include "volstream/core/math.h"

namespace vs::test {
// `count` random points (deterministic for a seed) in the box of `vertices` grown by 5% of its
// size on every side: mostly in a mesh, some around it.
std::vector<vec3f> points_around(std::span<const vec3f> vertices, int count, uint32_t seed);
}  // namespace vs::test

#include "volstream/umesh/mesh_data.h"
#include "volstream/umesh/umesh.h"

namespace vs::test {
// A demo mesh (umesh/demo.h) of one step as the renderer takes it, with its two point fields.
struct DemoMesh {
  MeshData data;
  WorldTransform transform;
  UMesh mesh;
  std::vector<float> density, linear;
};
DemoMesh demo_mesh(const std::string& name, uint64_t elements);
// Expects the element BVH's probe of `values` at `points` to equal the brute force (NaN at the
// same points, else relative 1e-5); returns how many points lie in an element.
int expect_probe_is_brute_force(const UMesh& mesh, const WorldTransform& transform, const float* values,
                                const std::vector<vec3f>& points);
// The point or cell field `name` of a mesh as the renderer samples it (umesh/from_mesh_data.h),
// and the array `name` as read; std::runtime_error if there is none.
std::vector<float> mesh_field(const MeshData& mesh, const std::string& name);
const MeshArray& array_named(const std::vector<MeshArray>& arrays, const std::string& name);
// Expects mesh `b`'s field `b_field` to probe as mesh `a`'s `a_field` at 4,000 points around b
// (those `compared` holds, in world coordinates, if given): NaN at the same points, else within
// relative 1e-5, and an eighth of them inside.
void expect_probes_alike(const MeshData& a, const std::string& a_field, const MeshData& b, const std::string& b_field,
                         bool (*compared)(const vec3d&) = nullptr);
}  // namespace vs::test
