// The native dataset reader on a mesh stored in the compact encoding (issue 13): a small mixed
// mesh with one of its files patched, then opened (check_compact_mesh), its macrocells built
// from the compact leaves, probed (also by brute force) and rendered; and opened deferred, as a
// data-parallel rank does (its mesh index: tree, leaf records, stored macrocells), restricted to a share
// read part by part, probed and rendered.
#include "fuzz_util.h"
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
  const std::vector<std::filesystem::path> files = {
      work / "manifest.json",         work / "compact_nodes.bin",
      work / "compact_leaves.bin",    work / "compact_bytes.bin",
      work / "compact_submeshes.bin", work / "compact_vertices.bin",
      work / "mesh_macrocells.bin",   work / "fields/0_density/step_000000.f32"};
  if (!fuzz::apply_patch(files, data, size)) return 0;
  fuzz::exercise_mesh_dataset(work);
  return 0;
}
