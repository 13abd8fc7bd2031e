// The native dataset reader: a valid small dataset with one of its files patched, read whole and
// as a data-parallel rank reads it (ABRs deferred, then its share's chunks; mpi/amr_share.h).
// Two bases, picked by bit 6 of the first byte: a raw grid of 24 cells (one brick, one ABR) and a
// jet demo of 10^4 cells (thousands of ABRs in many chunks, of which a rank reads some).
#include "fuzz_util.h"
#include "volstream/amr/abrs.h"
#include "volstream/amr/demo.h"
#include "volstream/amr/probe.h"
#include "volstream/io/dataset.h"
#include "volstream/io/raw_grid.h"
#include "volstream/mpi/amr_share.h"

#include <fstream>
#include <vector>

namespace {
std::filesystem::path make_base(const std::filesystem::path& dir) {
  using namespace vs;
  std::vector<float> v(4 * 3 * 2);
  for (size_t i = 0; i < v.size(); ++i) v[i] = float(i);
  std::ofstream(dir / "g.raw", std::ios::binary).write((const char*)v.data(), std::streamsize(v.size() * 4));
  RawGridInput in;
  in.files = {dir / "g.raw"};
  in.dims = {4, 3, 2};
  auto source = open_raw_grid(in);
  convert_to_dataset(*source, dir / "base", ConvertOptions::silent());
  return dir / "base";
}

std::filesystem::path make_jet_base(const std::filesystem::path& dir) {
  auto source = vs::make_demo({"jet", 10000, 1});
  vs::ConvertOptions options = vs::ConvertOptions::silent();
  options.fields = {"pressure"};
  convert_to_dataset(*source, dir / "jet", options);
  return dir / "jet";
}

// Rank 0 of 2's share, read as ParallelRenderer reads it.
void restrict_to_a_share(vs::Dataset& ds) {
  using namespace vs;
  DatasetPart part;
  part.owned = partition_bricks(ds.topology().bricks, 2).regions[0];
  RankShare share = read_rank_share(ds, part.owned, IntegratorSettings{});
  part.abrs = std::move(share.abrs);
  part.bricks = std::move(share.bricks);
  ds.restrict_to(std::move(part));
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("dataset");
  static const auto base = make_base(dir);
  static const auto jet = make_jet_base(dir);
  const bool on_jet = size > 0 && (data[0] & 0x40);
  const auto work = dir / "work";
  fuzz::copy_tree(on_jet ? jet : base, work);
  const std::vector<std::filesystem::path> files = {
      work / "manifest.json",
      work / "bricks.bin",
      work / "abrs.bin",
      work / "abr_bricks.bin",
      work / "cells.bin",
      work / "abr_bvh.bin",
      work / "abr_chunks.bin",
      work / (on_jet ? "fields/0_pressure/step_000000.f32" : "fields/0_scalar/step_000000.f32")};
  if (!fuzz::apply_patch(files, data, size)) return 0;
  for (const TopologyLoad load : {TopologyLoad::whole, TopologyLoad::deferred})
    fuzz::expect_clean([&] {
      Dataset ds(work, load);
      if (load == TopologyLoad::deferred) restrict_to_a_share(ds);
      const auto values = ds.load_values(0, 0);
      const Bvh bvh = build_abr_bvh(ds.topology());
      (void)probe_points(ds.topology(), bvh, values.data(), {vec3f(1.f, 1.f, 1.f), vec3f(3.5f, 2.5f, 1.5f)});
    });
  return 0;
}
