// The native dataset reader on a mesh stored in the compact encoding (issue 13): a small mixed
// mesh with one of its files patched, then opened (check_compact_mesh), its macrocells built
// from the compact leaves, probed (also by brute force) and rendered.
#include "fuzz_util.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/frame/look.h"
#include "volstream/io/dataset.h"
#include "volstream/io/mesh_convert.h"

#include <vector>

namespace {
std::filesystem::path make_base(const std::filesystem::path& dir) {
  using namespace vs;
  auto series = make_mesh_demo_series({"mixed", 200, 1});
  ConvertOptions options = ConvertOptions::silent();
  options.mesh_encoding = MeshEncoding::compact;
  convert_mesh_to_dataset(*series, dir / "base", options);
  return dir / "base";
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("compact_dataset");
  static const auto base = make_base(dir);
  const auto work = dir / "work";
  fuzz::copy_tree(base, work);
  const std::vector<std::filesystem::path> files = {work / "manifest.json",
                                                    work / "compact_nodes.bin",
                                                    work / "compact_leaves.bin",
                                                    work / "compact_indices.bin",
                                                    work / "compact_submeshes.bin",
                                                    work / "compact_vertices.bin",
                                                    work / "fields/0_density/step_000000.f32"};
  if (!fuzz::apply_patch(files, data, size)) return 0;
  fuzz::expect_clean([&] {
    Dataset ds(work);
    FrameRenderer renderer(ds, Device::cpu);
    const std::vector<vec3d> points = {vec3d(0.5, 0.5, 0.5), vec3d(0.1, 0.9, 0.2)};
    (void)renderer.probe(0, 0, points);
    (void)probe_brute_force(ds, 0, 0, points);
    FrameRequest r;
    r.width = r.height = 8;
    r.tf = make_transfer_function(ds.manifest(), 0, {0}, {});
    r.camera = default_view(ds, r.width, r.height);
    (void)renderer.render(r);
  });
  return 0;
}
