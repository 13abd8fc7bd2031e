// A mesh stored in the compact encoding (issue 13) against the same mesh stored in the reference
// encoding: the same pictures (DVR and an isosurface, two steps), the same probes at random
// points (fast and brute force), the same macrocell ranges; the reader refuses damaged files
// with one line naming the file, and reference-only requests with a UsageError.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <regex>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/cuda/backend.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/frame/look.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/io/vtu.h"
#include "volstream/render/integrators/umesh_renderer.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

fs::path convert_holes(MeshEncoding encoding) {
  const fs::path dir = test::scratch_dir(encoding == MeshEncoding::compact ? "holes_compact" : "holes_reference");
  auto series = make_mesh_demo_series({"holes", 6000, 2});
  ConvertOptions options = ConvertOptions::silent();
  options.mesh_encoding = encoding;
  convert_mesh_to_dataset(*series, dir, options);
  return dir;
}

const fs::path& compact_dir() {
  static const fs::path dir = convert_holes(MeshEncoding::compact);
  return dir;
}
const Dataset& compact() {
  static const Dataset ds(compact_dir());
  return ds;
}
const Dataset& reference() {
  static const Dataset ds(convert_holes(MeshEncoding::reference));
  return ds;
}

FrameRequest request(const Dataset& ds, int step) {
  FrameRequest r;
  r.width = 48;
  r.height = 40;
  r.step = step;
  r.field = ds.manifest().field_index("density");
  TransferFunctionRequest tf;
  tf.opacity = {{0.03, 0.0}, {0.3, 0.2}, {1.1, 0.6}};
  r.tf = make_transfer_function(ds.manifest(), r.field, {0, 1}, tf);
  r.camera = default_view(ds, r.width, r.height);
  r.integrator.iso_count = 1;
  r.integrator.iso[0] = 0.4f;
  return r;
}

// How far the compact encoding's values may be from the reference's: no quantization, only the
// rounding of a paired tet's solve with its corners in another order (relative to max(1, |v|)).
constexpr float kPairRounding = 1e-5f;

double max_difference(const Image& a, const Image& b) {
  double worst = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) worst = std::max(worst, double(std::fabs(a.rgba[i] - b.rgba[i])));
  return worst;
}

TEST(CompactDataset, StoresNoReferenceAndRendersWhatTheReferenceDatasetDoes) {
  ASSERT_TRUE(compact().is_compact_mesh());
  ASSERT_FALSE(reference().is_compact_mesh());
  EXPECT_THROW((void)compact().mesh(), std::logic_error);
  EXPECT_EQ(compact().manifest().fields[0].step_ranges[1].hi, reference().manifest().fields[0].step_ranges[1].hi);
  FrameRenderer a(reference(), Device::cpu), b(compact(), Device::cpu);
  for (int step : {0, 1}) {
    const Image want = a.render(request(reference(), step)), got = b.render(request(compact(), step));
    double alpha = 0;
    for (size_t i = 3; i < want.rgba.size(); i += 4) alpha += want.rgba[i];
    EXPECT_GT(alpha, 1.0) << "an empty picture proves nothing";
    // Paired tets keep their corners in another order (umesh/compact.h), so their barycentric
    // solves round differently: a few float ulps, measured up to 1.5e-6 here.
    EXPECT_LT(max_difference(want, got), kPairRounding) << "step " << step;
  }
}

// As the reference's (MeshFrame.DrawsFromTheMappedFilesWithoutCopyingThem): a whole load maps
// the compact arrays it stores (all but source_vertex), and drawing writes to none of them.
TEST(CompactDataset, DrawsFromTheMappedFilesWithoutCopyingThem) {
  FrameRenderer renderer(compact(), Device::cpu);
  renderer.render(request(compact(), 0));
  const CompactMesh& mesh = compact().compact_mesh();
  EXPECT_TRUE(mesh.nodes.is_view());
  EXPECT_TRUE(mesh.leaves.is_view());
  EXPECT_TRUE(mesh.bytes.is_view());
  EXPECT_TRUE(mesh.submeshes.is_view());
  EXPECT_TRUE(mesh.vertices.is_view());
}

TEST(CompactDataset, ProbesEqualTheReferenceAtRandomPoints) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  std::vector<vec3d> points(3000);
  for (vec3d& p : points) p = {u(rng), u(rng), u(rng)};
  FrameRenderer a(reference(), Device::cpu), b(compact(), Device::cpu);
  const std::vector<float> want = a.probe(0, 1, points), got = b.probe(0, 1, points);
  const std::vector<double> brute = probe_brute_force(compact(), 0, 1, points);
  int inside = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(std::isnan(want[i]), std::isnan(got[i])) << i;
    ASSERT_EQ(std::isnan(want[i]), std::isnan(brute[i])) << i;
    if (std::isnan(want[i])) continue;
    ++inside;
    EXPECT_NEAR(got[i], want[i], kPairRounding * std::max(1.f, std::fabs(want[i]))) << i;
    EXPECT_NEAR(brute[i], want[i], 1e-5 * std::max(1.0, std::fabs(double(want[i])))) << i;
  }
  EXPECT_GT(inside, 300);
}

// A grid of 12^3 hexahedra (no tets: its leaves' vertex tables hold about two entries an element,
// so the compact bytes are about 13.5 an element, where the manifest's bound once allowed 9 and
// such a dataset converted but did not load) probes what its reference encoding probes.
TEST(CompactDataset, AllHexMeshLoadsAndProbesAsTheReference) {
  constexpr int n = 12;
  MeshData m;
  auto id = [](int i, int j, int k) { return uint64_t(i + (n + 1) * (j + (n + 1) * k)); };
  MeshArray field{"f", 1, {}};
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        m.points.push_back(vec3d(i, j, k) / double(n));
        field.values.push_back(std::sin(0.7 * i) + std::cos(0.5 * j) * k);
      }
  m.point_data = {field};
  m.cell_offsets = {0};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        for (uint64_t v : {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1),
                           id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)})
          m.connectivity.push_back(v);
        m.cell_offsets.push_back(m.connectivity.size());
        m.cell_types.push_back(uint8_t(CellType::hex));
      }
  const fs::path dir = test::scratch_dir("all_hex");
  write_vtu(dir / "hexes.vtu", m);
  for (MeshEncoding encoding : {MeshEncoding::compact, MeshEncoding::reference}) {
    ConvertOptions options = ConvertOptions::silent();
    options.mesh_encoding = encoding;
    convert_mesh_to_dataset(*open_mesh_files({dir / "hexes.vtu"}),
                            dir / (encoding == MeshEncoding::compact ? "c" : "r"), options);
  }
  const Dataset compact_hexes(dir / "c"), reference_hexes(dir / "r");
  ASSERT_TRUE(compact_hexes.is_compact_mesh());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<vec3d> points(2000);
  for (vec3d& p : points) p = {u(rng), u(rng), u(rng)};
  FrameRenderer a(reference_hexes, Device::cpu), b(compact_hexes, Device::cpu);
  const std::vector<float> want = a.probe(0, 0, points), got = b.probe(0, 0, points);
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_FALSE(std::isnan(want[i])) << i;
    EXPECT_NEAR(got[i], want[i], kPairRounding * std::max(1.f, std::fabs(want[i]))) << i;
  }
}

TEST(CompactDataset, MacrocellsAndTheirRangesEqualTheReferences) {
  UMeshRenderer a(reference().mesh(), reference().mesh_accel(), reference().manifest().transform);
  UMeshRenderer b(compact().compact_mesh(), compact().manifest().transform);
  ASSERT_EQ(a.region_count(), b.region_count());
  const std::vector<Range> want = a.ranges(reference().load_values(0, 1).data());
  const std::vector<Range> got = b.ranges(compact().load_values(0, 1).data());
  for (size_t r = 0; r < want.size(); ++r) {
    EXPECT_EQ(want[r].lo, got[r].lo) << r;
    EXPECT_EQ(want[r].hi, got[r].hi) << r;
    EXPECT_EQ(a.macrocells().step_width[r], b.macrocells().step_width[r]) << r;
  }
  EXPECT_LT(b.bytes().total(), a.bytes().total() / 2);
}

TEST(CompactDataset, ReferenceOnlyRequestsAreRefusedInOneLine) {
  FrameRenderer renderer(compact(), Device::cpu);
  FrameRequest r = request(compact(), 0);
  r.mesh_encoding = MeshEncoding::reference;
  EXPECT_THROW(renderer.render(r), UsageError);
  EXPECT_THROW(renderer.probe(0, 0, {vec3d(0.5)}, MeshEncoding::reference), UsageError);
}

// The GPU renders and probes a stored compact mesh as the CPU does (the same kernel source).
TEST(CompactDatasetCuda, EqualsTheCpu) {
  if (!cuda::cuda_available()) GTEST_SKIP() << "no CUDA device";
  FrameRenderer cpu(compact(), Device::cpu), gpu(compact(), Device::cuda);
  FrameRequest dvr = request(compact(), 1), iso = request(compact(), 1);
  iso.integrator.iso_count = 1;
  iso.integrator.iso[0] = 0.4f;
  iso.integrator.shade = 1;
  for (const FrameRequest& r : {dvr, iso}) {
    const Image a = cpu.render(r), b = gpu.render(r);
    double sum = 0, alpha = 0;
    for (size_t i = 0; i < a.rgba.size(); ++i) sum += std::fabs(a.rgba[i] - b.rgba[i]);
    for (size_t i = 3; i < a.rgba.size(); i += 4) alpha += a.rgba[i];
    EXPECT_GT(alpha, 1.0);
    EXPECT_LT(sum / double(a.rgba.size()), 1e-3);
  }
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.1, 1.1);
  std::vector<vec3d> points(1000);
  for (vec3d& p : points) p = {u(rng), u(rng), u(rng)};
  const std::vector<float> a = cpu.probe(0, 1, points), b = gpu.probe(0, 1, points);
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(std::isnan(a[i]), std::isnan(b[i])) << i;
    if (!std::isnan(a[i])) {
      EXPECT_NEAR(a[i], b[i], kPairRounding * std::max(1.f, std::fabs(a[i])));
    }
  }
}

// --device auto takes the GPU wherever the encoding has a CUDA path: a stored compact mesh has
// one, a compact mesh built at load from a reference dataset has not.
TEST(CompactDataset, AutoDeviceIsTheGpuWhereTheEncodingRunsThere) {
  const Device gpu_if_any = cuda::cuda_available() ? Device::cuda : Device::cpu;
  EXPECT_EQ(resolve_device("auto", compact(), MeshEncoding::stored), gpu_if_any);
  EXPECT_EQ(resolve_device("auto", compact(), MeshEncoding::compact), gpu_if_any);
  EXPECT_EQ(resolve_device("auto", reference(), MeshEncoding::stored), gpu_if_any);
  EXPECT_EQ(resolve_device("auto", reference(), MeshEncoding::compact), Device::cpu);
  EXPECT_EQ(resolve_device("cpu", compact(), MeshEncoding::stored), Device::cpu);
}

// A copy of the compact dataset with `file` changed by `damage`; the InputError it gives.
std::string open_damaged(const std::string& name, const std::string& file,
                         const std::function<void(std::vector<char>&)>& damage) {
  const fs::path dir = test::damaged_copy(compact_dir(), "compact_damaged_" + name, file, damage);
  return test::input_error_line([&] { Dataset ds(dir); });
}

template <typename T>
void patch(std::vector<char>& bytes, size_t record, size_t offset, T value) {
  std::memcpy(bytes.data() + record + offset, &value, sizeof(T));
}

TEST(CompactDataset, ReaderRefusesDamagedFilesNamingThem) {
  auto has = [](const std::string& line, const char* file, const char* what) {
    return line.find(file) != std::string::npos && line.find(what) != std::string::npos;
  };
  std::string line = open_damaged("truncated", "compact_bytes.bin", [](auto& b) { b.resize(b.size() - 2); });
  EXPECT_TRUE(has(line, "compact_bytes.bin", "")) << line;
  // Leaf 0's bytes start the file: its vertex table, then its corners.
  line = open_damaged("table", "compact_bytes.bin", [](auto& b) { patch<uint16_t>(b, 0, 0, 65535); });
  EXPECT_TRUE(has(line, "compact_bytes.bin", "outside its sub-mesh")) << line;
  const size_t table_bytes = 2 * compact().compact_mesh().leaves[0].table_size();
  ASSERT_LT(table_bytes, 512u);
  line = open_damaged("corner", "compact_bytes.bin", [&](auto& b) { patch<uint8_t>(b, table_bytes, 0, 255); });
  EXPECT_TRUE(has(line, "compact_bytes.bin", "outside its vertex table")) << line;
  line = open_damaged("leaf_count", "compact_leaves.bin",
                      [](auto& b) { patch<uint8_t>(b, 12 * 3, offsetof(CompactLeaf, counts), 40); });
  EXPECT_TRUE(has(line, "compact_leaves.bin", "leaf 3")) << line;
  line = open_damaged("pairs", "compact_leaves.bin",
                      [](auto& b) { patch<uint8_t>(b, 12 * 2, offsetof(CompactLeaf, tet_pairs), 200); });
  EXPECT_TRUE(has(line, "compact_leaves.bin", "pairs more tets")) << line;
  line = open_damaged("leaf_run", "compact_leaves.bin",
                      [](auto& b) { patch<uint32_t>(b, 12 * 5, offsetof(CompactLeaf, first_byte), 0xfffff000u); });
  EXPECT_TRUE(has(line, "compact_leaves.bin", "beyond its sub-mesh")) << line;
  // The root pointing at itself (a cycle), and a node whose children are leaves reached twice.
  line = open_damaged("cycle", "compact_nodes.bin",
                      [](auto& b) { patch<uint32_t>(b, 0, offsetof(CompactNode, first), 0); });
  EXPECT_TRUE(has(line, "compact_nodes.bin", "node 0")) << line;
  const uint32_t last = uint32_t(compact().compact_mesh().nodes.size() - 1);
  line = open_damaged("twice", "compact_nodes.bin",
                      [&](auto& b) { patch<uint32_t>(b, 80 * size_t(last), offsetof(CompactNode, first), 0); });
  EXPECT_TRUE(has(line, "compact_nodes.bin", "")) << line;
  EXPECT_NE(line, "accepted");
  // A child box shrunk so that it no longer holds its child.
  line =
      open_damaged("box", "compact_nodes.bin", [](auto& b) { patch<uint8_t>(b, 0, offsetof(CompactNode, upper), 0); });
  EXPECT_TRUE(has(line, "compact_nodes.bin", "does not hold")) << line;
  line = open_damaged("submesh", "compact_submeshes.bin", [](auto& b) { patch<uint32_t>(b, 0, 0, 7); });
  EXPECT_TRUE(has(line, "compact_submeshes.bin", "start at 0")) << line;
  line = open_damaged("manifest", "manifest.json", [](auto& b) {
    const std::string text(b.begin(), b.end());
    const std::string edited =
        std::regex_replace(text, std::regex("\"compact_leaves.bin\": \\d+"), "\"compact_leaves.bin\": 3");
    b.assign(edited.begin(), edited.end());
  });
  EXPECT_TRUE(has(line, "compact_leaves.bin", "")) << line;
  EXPECT_NE(line, "accepted");
}

}  // namespace
}  // namespace vs
