// bench integrators: the same view with the ABR (tent) integrator and the kd-tree block raycaster
// (nearest and trilinear), on the CPU: render time and the image difference to the ABR image, and
// the block raycaster's vertex values (trilinear's once-per-field preprocessing) timed apart.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "commands.h"
#include "volstream/core/error.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/frame/look.h"
#include "volstream/io/dataset.h"
#include "volstream/io/image.h"

namespace vs::cli {
namespace {

struct BenchIntegratorsArgs {
  std::string dir, field;
  int step = 0, repeat = 3;
  uint32_t size = 512;
  double rate = 2;
};

// The field's range, log10 over up to 8 decades when positive; inferno with the default ramp.
TransferFunctionSpec bench_tf(const FieldInfo& f, int step) {
  TransferFunctionSpec spec;
  Range r = f.step_ranges.at(size_t(step));
  if (!(r.lo <= r.hi)) r = {0.f, 1.f};
  spec.log_scale = r.lo > 0.f;
  if (spec.log_scale) r.lo = std::max(r.lo, r.hi * 1e-8f);
  spec.lo = r.lo;
  spec.hi = r.hi;
  spec.colors = builtin_color_map("inferno");
  spec.opacity = default_opacity_ramp(0.5f);
  return spec;
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

// Renders `repeat` times; returns the last image and the best render-stage time.
Image best_render(FrameRenderer& renderer, const FrameRequest& r, int repeat, double& best) {
  Image img;
  best = 1e300;
  for (int i = 0; i < std::max(repeat, 1); ++i) {
    FrameReport report;
    img = renderer.render(r, &report);
    best = std::min(best, report.seconds.render);
  }
  return img;
}

void run_bench_integrators(const BenchIntegratorsArgs& a) {
  const Dataset ds(a.dir);
  const DatasetManifest& m = ds.manifest();
  const int field = a.field.empty() ? 0 : m.field_index(a.field);
  if (field < 0) throw UsageError("no field '" + a.field + "' in " + a.dir);
  if (a.step < 0 || a.step >= m.step_count()) throw UsageError("--step out of range");
  FrameRequest r;
  r.field = field;
  r.step = a.step;
  r.tf = bench_tf(m.fields[size_t(field)], a.step);
  r.width = r.height = a.size;
  r.integrator.rate = float(a.rate);
  r.integrator.jitter = 0;  // same sample positions every run: comparable images
  r.stored_ranges = true;
  r.camera = default_view(ds, a.size, a.size);
  FrameRenderer renderer(ds, Device::cpu);

  std::printf("bench integrators: %s, field %s, %ux%u on the CPU, rate %g, best of %d\n", a.dir.c_str(),
              m.fields[size_t(field)].name.c_str(), a.size, a.size, a.rate, a.repeat);
  double t_abr = 0;
  const Image ref = best_render(renderer, r, a.repeat, t_abr);
  std::printf("\n%-22s %10s %12s %12s\n", "integrator", "ms", "RMSE vs abr", "max vs abr");
  double coverage = 0;  // mean alpha: how much of the image the comparison covers
  for (size_t i = 3; i < ref.rgba.size(); i += 4) coverage += ref.rgba[i];
  coverage /= double(std::max<size_t>(ref.rgba.size() / 4, 1));
  std::printf("%-22s %10.1f %12s %12s   (mean alpha %.3f)\n", "abr (tent)", 1e3 * t_abr, "-", "-", coverage);
  // Vertex values for trilinear: made once per field values by the first trilinear frame, not
  // per render, so reported on their own and not included in the render times.
  double t_vertex = 0;
  r.kind = IntegratorKind::blocks;
  for (Reconstruction rec : {Reconstruction::nearest, Reconstruction::trilinear}) {
    r.reconstruction = rec;
    if (rec == Reconstruction::trilinear) {
      FrameReport first;
      renderer.render(r, &first);
      t_vertex = first.vertex_seconds;
    }
    double t = 0;
    const Image img = best_render(renderer, r, a.repeat, t);
    const Diff d = image_diff(ref, img);
    std::printf("%-22s %10.1f %12.4f %12.4f\n", rec == Reconstruction::nearest ? "blocks nearest" : "blocks trilinear",
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
