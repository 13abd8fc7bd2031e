// bench integrators: the same view with the ABR (tent) integrator and the kd-tree block raycaster
// (nearest and trilinear), on the CPU: render time and the image difference to the ABR image, and
// the block raycaster's vertex values (trilinear's once-per-field preprocessing) timed apart.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "commands.h"
#include "volstream/backend/stopwatch.h"
#include "volstream/core/error.h"
#include "volstream/io/dataset.h"
#include "volstream/io/image.h"
#include "volstream/render/integrators/abr_renderer.h"
#include "volstream/render/integrators/block_renderer.h"

namespace vs::cli {
namespace {

struct BenchIntegratorsArgs {
  std::string dir, field;
  int step = 0, repeat = 3;
  uint32_t size = 512;
  double rate = 2;
};

// The field's range, log10 over up to 8 decades when positive; inferno with the default ramp.
TransferTable bench_tf(const FieldInfo& f, int step) {
  TransferFunctionSpec spec;
  Range r = f.step_ranges.at(size_t(step));
  if (!(r.lo <= r.hi)) r = {0.f, 1.f};
  spec.log_scale = r.lo > 0.f;
  if (spec.log_scale) r.lo = std::max(r.lo, r.hi * 1e-8f);
  spec.lo = r.lo;
  spec.hi = r.hi;
  spec.colors = builtin_color_map("inferno");
  spec.opacity = default_opacity_ramp(0.5f);
  return TransferTable(spec);
}

struct Diff {
  double rmse = 0, max = 0;
};
Diff image_diff(const Image& a, const Image& b) {
  const std::vector<float> x = composite_rgb(a, vec3f(0.f)), y = composite_rgb(b, vec3f(0.f));
  Diff d;
  for (size_t i = 0; i < x.size(); ++i) {
    const double e = std::fabs(double(x[i]) - y[i]);
    d.rmse += e * e;
    d.max = std::max(d.max, e);
  }
  d.rmse = std::sqrt(d.rmse / double(std::max<size_t>(x.size(), 1)));
  return d;
}

// Best wall time of `repeat` calls of f.
template <typename F>
double best_seconds(int repeat, F&& f) {
  double best = 1e300;
  for (int i = 0; i < std::max(repeat, 1); ++i) {
    const Stopwatch watch;
    f();
    best = std::min(best, watch.seconds());
  }
  return best;
}

void run_bench_integrators(const BenchIntegratorsArgs& a) {
  const Dataset ds(a.dir);
  const DatasetManifest& m = ds.manifest();
  const int field = a.field.empty() ? 0 : m.field_index(a.field);
  if (field < 0) throw UsageError("no field '" + a.field + "' in " + a.dir);
  if (a.step < 0 || a.step >= m.step_count()) throw UsageError("--step out of range");
  const std::vector<float> values = ds.load_values(field, a.step);
  const TransferTable tf = bench_tf(m.fields[size_t(field)], a.step);

  FrameSettings fs;
  fs.width = fs.height = a.size;
  fs.integrator.rate = float(a.rate);
  fs.integrator.jitter = 0;  // same sample positions every run: comparable images
  fs.skip = true;
  AmrRenderer abr(ds.topology(), m.transform);
  abr.classify(ds.load_abr_ranges(field, a.step), tf, fs.integrator, fs.skip);
  const Camera camera = default_camera(abr.world_bounds(), 1.0);

  BlockRenderer blocks(ds.topology(), m.transform);
  std::printf("bench integrators: %s, field %s, %ux%u on the CPU, rate %g, best of %d\n", a.dir.c_str(),
              m.fields[size_t(field)].name.c_str(), a.size, a.size, a.rate, a.repeat);
  std::printf("%zu bricks -> %zu blocks, kd-tree of %zu nodes built in %.3fs\n", ds.topology().bricks.size(),
              blocks.kd().blocks.size(), blocks.kd().nodes.size(), blocks.build_seconds());

  Image ref;
  const double t_abr =
      best_seconds(a.repeat, [&] { ref = abr.render(Device::cpu, values.data(), tf, nullptr, nullptr, camera, fs); });
  std::printf("\n%-22s %10s %12s %12s\n", "integrator", "ms", "RMSE vs abr", "max vs abr");
  double coverage = 0;  // mean alpha: how much of the image the comparison covers
  for (size_t i = 3; i < ref.rgba.size(); i += 4) coverage += ref.rgba[i];
  coverage /= double(std::max<size_t>(ref.rgba.size() / 4, 1));
  std::printf("%-22s %10.1f %12s %12s   (mean alpha %.3f)\n", "abr (tent)", 1e3 * t_abr, "-", "-", coverage);
  // Vertex values for trilinear: computed once per field values (set_fields), not per render,
  // so timed on their own and not included in the trilinear render time.
  const double t_vertex = best_seconds(a.repeat, [&] { blocks.set_fields(values.data()); });
  const TfView view = tf.view();
  for (Reconstruction r : {Reconstruction::nearest, Reconstruction::trilinear}) {
    BlockFrame frame;
    frame.width = frame.height = a.size;
    frame.settings.rate = float(a.rate);
    frame.settings.reconstruction = r;
    Image img;
    const double t = best_seconds(a.repeat, [&] { img = blocks.render(&view, camera, frame); });
    const Diff d = image_diff(ref, img);
    std::printf("%-22s %10.1f %12.4f %12.4f\n", r == Reconstruction::nearest ? "blocks nearest" : "blocks trilinear",
                1e3 * t, d.rmse, d.max);
  }
  std::printf("%-22s %10.1f   (once per field values, not in the render times)\n", "blocks vertex values",
              1e3 * t_vertex);
  std::printf(
      "(differences in linear RGB over black, per channel; the tent basis and the cell-centred\n"
      " reconstructions differ by design, so small non-zero values are expected)\n");
}

}  // namespace

void add_bench_integrators(CLI::App& bench) {
  auto a = std::make_shared<BenchIntegratorsArgs>();
  auto* cmd =
      bench.add_subcommand("integrators", "ABR tent integrator vs kd-tree block raycaster: time and image difference");
  cmd->add_option("dataset", a->dir, "dataset directory")->required();
  cmd->add_option("--field", a->field, "field (default: the first)");
  cmd->add_option("--step", a->step, "time step")->capture_default_str();
  cmd->add_option("--size", a->size, "image size (square, at most 8192)")
      ->check(CLI::Range(1u, 8192u))
      ->capture_default_str();
  cmd->add_option("--rate", a->rate, "samples per cell width")->capture_default_str();
  cmd->add_option("--repeat", a->repeat, "renders per integrator (best time kept)")->capture_default_str();
  cmd->callback([a] { run_bench_integrators(*a); });
}

}  // namespace vs::cli
