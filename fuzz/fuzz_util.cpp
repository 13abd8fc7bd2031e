#include "fuzz_util.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include "volstream/core/error.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/frame/look.h"
#include "volstream/io/dataset.h"
#include "volstream/mpi/mesh_share.h"

namespace vs::fuzz {
namespace fs = std::filesystem;

fs::path scratch(const char* name) {
  fs::path dir = fs::temp_directory_path() / ("volstream_fuzz_" + std::string(name) + "_" + std::to_string(getpid()));
  fs::create_directories(dir);
  // Check stamps (io/check_stamp.h) in the scratch directory, not the user's cache: datasets the
  // harness leaves unchanged for a while are then opened through their stamps too.
  setenv("VOLSTREAM_CHECK_STAMPS", (dir / "check_stamps").c_str(), 1);
  return dir;
}

// Through streams, whose reads and writes retry on EINTR: std::filesystem's copies (sendfile)
// give up when libFuzzer's timer signal interrupts them, a harness failure and not a finding.
void copy_file_contents(const fs::path& from, const fs::path& to) {
  std::ifstream in(from, std::ios::binary);
  std::ofstream out(to, std::ios::binary | std::ios::trunc);
  // An empty file (an OpenFOAM case's CASE.foam) copies as nothing: `<<` of an empty buffer fails.
  if (in.peek() != std::ifstream::traits_type::eof()) out << in.rdbuf();
  if (!in || !out) throw std::runtime_error("fuzz harness: cannot copy " + from.string());
}

void copy_tree(const fs::path& from, const fs::path& to) {
  fs::remove_all(to);
  fs::create_directories(to);
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(from)) {
    const fs::path target = to / fs::relative(e.path(), from);
    if (e.is_directory())
      fs::create_directories(target);
    else
      copy_file_contents(e.path(), target);
  }
}

bool apply_patch(const std::vector<fs::path>& files, const uint8_t* data, size_t size) {
  size_t patched = 0;
  return apply_patch(files, data, size, patched);
}

bool apply_patch(const std::vector<fs::path>& files, const uint8_t* data, size_t size, size_t& patched) {
  if (size < 5 || files.empty()) return false;
  patched = (data[0] & 0x7f) % files.size();
  const fs::path& file = files[patched];
  uint32_t offset;
  std::memcpy(&offset, data + 1, 4);
  std::string content;
  {
    std::ifstream in(file, std::ios::binary);
    content.assign(std::istreambuf_iterator<char>(in), {});
  }
  offset = content.empty() ? 0 : offset % uint32_t(content.size() + 1);
  if (data[0] & 0x80) {
    content.resize(offset);
  } else {
    const size_t n = size - 5;
    if (content.size() < offset + n) content.resize(offset + n);
    std::memcpy(content.data() + offset, data + 5, n);
  }
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(content.data(), std::streamsize(content.size()));
  return true;
}

void expect_clean(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError&) {
  } catch (const UsageError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unexpected exception: %s\n", e.what());
    std::abort();
  }
}

namespace {
// A rank's share, chosen as ParallelRenderer chooses it (rank 0 of 2), before anything renders.
void restrict_to_a_share(Dataset& ds) {
  const MeshIndex index = ds.mesh_index();
  const std::vector<vec3d> points = index.item_points();
  const Partition p = partition_points(points, 2, index.item_elements);
  DatasetPart part;
  part.mesh_items = mesh_share(index, points, p.regions[0], IntegratorSettings{}).items;
  part.mesh_grid = index.cells.grid;
  part.owned = p.regions[0];
  part.world_bounds = world_bounds(ds);
  ds.restrict_to(std::move(part));
}
}  // namespace

void exercise_mesh_dataset(const fs::path& dir) {
  for (const TopologyLoad load : {TopologyLoad::whole, TopologyLoad::deferred}) exercise_mesh_dataset(dir, load);
}

void exercise_mesh_dataset(const fs::path& dir, TopologyLoad load) {
  expect_clean([&] {
    Dataset ds(dir, load);
    if (load == TopologyLoad::deferred) restrict_to_a_share(ds);
    FrameRenderer renderer(ds, Device::cpu);
    const std::vector<vec3d> points = {vec3d(0.5, 0.5, 0.5), vec3d(0.1, 0.9, 0.2)};
    (void)renderer.probe(0, 0, points);
    (void)probe_brute_force(ds, 0, 0, points);
    FrameRequest r;
    r.width = r.height = 8;
    r.tf = make_transfer_function(ds.manifest(), 0, {0}, {});
    r.camera = default_view(ds, r.width, r.height);
    (void)renderer.render(r);
    // Another field: the renderer's second ranges, from the per-region vertex lists it builds then.
    if (ds.manifest().fields.size() > 1) {
      r.field = 1;
      (void)renderer.render(r);
    }
  });
}

}  // namespace vs::fuzz
