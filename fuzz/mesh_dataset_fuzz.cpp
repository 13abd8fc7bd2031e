// The native dataset reader on a mesh dataset (kind umesh): a small mixed mesh, or a small tet
// mesh (whose walk records are stored), with one of its files patched, then opened, its BVH and
// macrocells built, probed (also by brute force) and rendered (the tets' stored walk records
// mapped and checked); and opened deferred as a data-parallel rank does (chunk boxes,
// macrocells), restricted to a share read part by part, probed and rendered.
#include "fuzz_util.h"
#include "volstream/io/dataset.h"
#include "volstream/io/mesh_convert.h"

#include <string>
#include <vector>

namespace {
const char* const kDemos[] = {"mixed", "tets"};

std::filesystem::path make_base(const std::filesystem::path& dir, const std::string& demo) {
  using namespace vs;
  auto series = make_mesh_demo_series({demo, 60, 1});
  convert_mesh_to_dataset(*series, dir / ("base_" + demo), ConvertOptions::silent());
  return dir / ("base_" + demo);
}

// Each demo's files, the tets' walk records and the macrocells' vertex lists among them.
std::vector<std::filesystem::path> files_of(const std::filesystem::path& work, const std::string& demo) {
  std::vector<std::filesystem::path> files = {
      work / "manifest.json",      work / "mesh_vertices.bin",   work / "mesh_elements.bin",
      work / "mesh_bvh_nodes.bin", work / "mesh_bvh_items.bin",  work / "mesh_neighbors.bin",
      work / "mesh_chunks.bin",    work / "mesh_macrocells.bin", work / "fields/0_density/step_000000.f32"};
  if (demo == "tets") files.push_back(work / "mesh_tet_walk.bin");
  for (const char* lists : {"mesh_region_first.bin", "mesh_region_vertices.bin"})
    if (std::filesystem::exists(work / lists)) files.push_back(work / lists);
  return files;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("mesh_dataset");
  static const std::filesystem::path bases[] = {make_base(dir, kDemos[0]), make_base(dir, kDemos[1])};
  // Each demo's working copy, made once; after an input only the copy it patched is restored.
  static const std::filesystem::path works[] = {dir / ("work_" + std::string(kDemos[0])),
                                                dir / ("work_" + std::string(kDemos[1]))};
  static std::vector<std::filesystem::path> files;
  static std::vector<int> file_demo;  // which demo files[i] belongs to
  if (files.empty()) {
    for (int d = 0; d < 2; ++d) {
      fuzz::copy_tree(bases[d], works[d]);
      for (const auto& f : files_of(works[d], kDemos[d])) files.push_back(f), file_demo.push_back(d);
    }
  }
  size_t patched = 0;
  if (!fuzz::apply_patch(files, data, size, patched)) return 0;
  const int d = file_demo[patched];
  fuzz::exercise_mesh_dataset(works[d]);
  fuzz::copy_tree(bases[d], works[d]);
  return 0;
}
