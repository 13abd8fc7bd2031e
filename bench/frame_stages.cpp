// Times the per-frame work that is not rendering, stage by stage, on the CPU: the ABR value
// ranges (tight and per brick), the classification and the refit of the BVH template, and for
// scale the BVH rebuild they replace. Each is repeated and reported as median, min and max ms.
//
//   volstream_bench_stages DIR [--field NAME] [--step N] [--repeat N] [--linear]
//
// The transfer function is the default opacity ramp over the field's range at that step, on a
// log scale unless --linear (as `volstream render --log`). Stream-level figures (read, upload,
// render) come from `volstream bench stream`; this driver isolates the stages it cannot split.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "volstream/accel/bvh_sah.h"
#include "volstream/accel/refit.h"
#include "volstream/amr/ranges.h"
#include "volstream/core/stopwatch.h"
#include "volstream/io/dataset.h"
#include "volstream/render/integrators/abr_renderer.h"
#include "volstream/render/optics/transfer_function.h"

namespace {

struct Args {
  std::string dir, field;
  int step = 0, repeat = 7;
  bool linear = false;
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(s + " needs a value");
      return argv[++i];
    };
    if (s == "--field")
      a.field = next();
    else if (s == "--step")
      a.step = std::stoi(next());
    else if (s == "--repeat")
      a.repeat = std::max(1, std::stoi(next()));
    else if (s == "--linear")
      a.linear = true;
    else if (a.dir.empty())
      a.dir = s;
    else
      throw std::runtime_error("unexpected argument " + s);
  }
  if (a.dir.empty())
    throw std::runtime_error("usage: volstream_bench_stages DIR [--field NAME] [--step N] [--repeat N] [--linear]");
  return a;
}

// Runs f `repeat` times and prints median, min and max milliseconds.
void time_stage(const char* name, int repeat, const std::function<void()>& f) {
  std::vector<double> ms;
  for (int r = 0; r < repeat; ++r) {
    const vs::Stopwatch watch;
    f();
    ms.push_back(1e3 * watch.seconds());
  }
  std::sort(ms.begin(), ms.end());
  std::printf("%-22s %9.2f %9.2f %9.2f\n", name, ms[ms.size() / 2], ms.front(), ms.back());
}

}  // namespace

int main(int argc, char** argv) try {
  using namespace vs;
  const Args args = parse(argc, argv);
  const Dataset ds(args.dir);
  const int field = args.field.empty() ? 0 : ds.manifest().field_index(args.field);
  if (field < 0) throw std::runtime_error("no field " + args.field);
  const AmrTopology& topo = ds.topology();
  const std::vector<float> values = ds.load_values(field, args.step);
  const Range r = value_range(values.data(), values.size());

  TransferFunctionSpec spec;
  spec.log_scale = !args.linear;
  spec.lo = spec.log_scale ? std::max(r.lo, r.hi * 1e-6f) : r.lo;
  spec.hi = r.hi;
  spec.colors = builtin_color_map("viridis");
  const TransferTable tf(spec);
  const IntegratorSettings iso;

  AmrRenderer renderer(topo, ds.manifest().transform);
  const std::vector<uint64_t> offsets = macrocell_offsets(topo.bricks);
  std::vector<Range> ranges = compute_abr_ranges(topo, values.data(), &offsets);
  std::vector<uint8_t> keep = classify_regions(ranges, tf, iso);
  std::vector<box3f> boxes;
  for (const Abr& a : topo.abrs) boxes.push_back(a.box);
  std::vector<BvhNode> nodes = renderer.template_bvh().nodes;

  std::printf("%s: %llu cells, %zu bricks, %zu ABRs, %zu ABR-brick pairs, %zu BVH nodes; %lld of %zu ABRs visible\n",
              args.dir.c_str(), (unsigned long long)topo.cell_count, topo.bricks.size(), topo.abrs.size(),
              topo.abr_bricks.size(), nodes.size(), (long long)std::count(keep.begin(), keep.end(), uint8_t(1)),
              keep.size());
  std::printf("%-22s %9s %9s %9s   (ms, %d runs)\n", "stage", "median", "min", "max", args.repeat);
  time_stage("ranges (tight)", args.repeat, [&] { ranges = compute_abr_ranges(topo, values.data(), &offsets); });
  time_stage("ranges (per brick)", args.repeat,
             [&] { compute_abr_ranges(topo, values.data(), &offsets, RangeMode::per_brick); });
  time_stage("classify", args.repeat, [&] { keep = classify_regions(ranges, tf, iso); });
  time_stage("refit", args.repeat, [&] { refit_bvh(nodes, boxes, keep); });
  time_stage("classify + refit", args.repeat, [&] { renderer.classify(ranges, tf, iso, true); });
  time_stage("rebuild (SAH BVH)", std::min(args.repeat, 3), [&] { build_bvh_sah(boxes); });
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "volstream_bench_stages: %s\n", e.what());
  return 2;
}
