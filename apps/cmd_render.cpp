// render: one image of a dataset (or a built-in demo) through the library's FrameRenderer.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>

#include "commands.h"
#include "render_options.h"
#include "volstream/amr/demo.h"
#include "volstream/backend/launch_times.h"
#include "volstream/backend/memory.h"
#include "volstream/core/error.h"
#include "volstream/core/stopwatch.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/io/atomic_file.h"
#include "volstream/io/cleanup.h"
#include "volstream/io/dataset.h"
#include "volstream/io/image.h"

namespace vs::cli {
namespace {

struct RenderArgs {
  std::string dir, demo, output;
  double cells = 1e6;
  int step = 0;
  RenderOptions render;  // shared with play and bench stream (render_options.h)
};

// A demo written to a fresh private directory (mkdtemp: never a planted path or link), removed
// again on exit and on Ctrl-C.
struct TempDemo {
  std::filesystem::path root, dir;
  std::unique_ptr<RemoveOnSignal> on_signal;
  TempDemo(const std::string& name, double cells) {
    std::string path = (std::filesystem::temp_directory_path() / ("volstream_render_" + name + "_XXXXXX")).string();
    if (!::mkdtemp(path.data()))
      input_error(path, std::string("cannot create a temporary directory: ") + std::strerror(errno));
    root = path;
    on_signal = std::make_unique<RemoveOnSignal>(root);
    dir = root / "dataset";
    try {
      auto source = make_demo({name, uint64_t(cells), 1});
      convert_to_dataset(*source, dir, ConvertOptions::silent());
    } catch (...) {
      std::error_code ec;
      std::filesystem::remove_all(root, ec);
      throw;
    }
  }
  ~TempDemo() {
    std::error_code ec;
    std::filesystem::remove_all(root, ec);
  }
};

void print_report(const Dataset& ds, const FrameRequest& r, const FrameReport& rep, double open_s, double cpu_s,
                  const std::string& output) {
  const TransferFunctionSpec& spec = r.tf;
  std::printf("device: %s\n", describe(rep.device).c_str());
  const bool mesh = ds.is_mesh(), abr = r.kind == IntegratorKind::abr && !mesh, skips = abr || mesh;
  std::printf("field %s step %d, range [%g, %g]%s, %llu of %llu %s visible%s\n",
              ds.manifest().fields[size_t(r.field)].name.c_str(), r.step, spec.lo, spec.hi,
              spec.log_scale ? " (log)" : "", (unsigned long long)rep.visible_regions,
              (unsigned long long)rep.region_count,
              mesh  ? "macrocells"
              : abr ? "ABRs"
                    : "blocks",
              skips && !r.skip ? " (no skipping)" : "");
  std::printf("integrator %s%s, %s optics\n",
              mesh  ? "mesh (element BVH, VTK shape functions)"
              : abr ? "abr"
                    : "blocks",
              skips ? "" : (r.reconstruction == Reconstruction::nearest ? " (nearest)" : " (trilinear)"),
              r.optics == OpticsKind::blackbody ? "blackbody" : "tf");
  const FrameTimes& t = rep.seconds;
  std::printf("load %.3fs, ranges %.4fs%s, classify %.4fs, refit %.4fs, upload %.4fs\n", open_s + t.read, t.ranges,
              r.stored_ranges ? " (stored)" : (skips ? "" : " (vertex values)"), t.classify, t.refit, t.upload);
  std::printf("render %ux%u: %.3fs (%.3fs CPU time), %.1f M samples, %.1f M samples/s -> %s\n", r.width, r.height,
              t.render, cpu_s, rep.samples * 1e-6, rep.samples * 1e-6 / std::max(t.render, 1e-9), output.c_str());
  std::printf("memory: %s\n", format_memory(memory_ledger().snapshot()).c_str());
  std::printf("launches: %s\n", format_launch_times(launch_times().snapshot()).c_str());
}

void run_render(RenderArgs a) {
  if (a.dir.empty() == a.demo.empty()) throw UsageError("give either a dataset directory or --demo jet|cosmo");
  check_image_output(a.output);  // before the work, not after
  Stopwatch open_watch;
  std::unique_ptr<TempDemo> demo;
  if (!a.demo.empty()) demo = std::make_unique<TempDemo>(a.demo, a.cells);
  const Dataset ds(demo ? demo->dir.string() : a.dir);
  const DatasetManifest& m = ds.manifest();
  if (a.step < 0 || a.step >= m.step_count())
    throw UsageError("step " + std::to_string(a.step) + " out of range 0.." + std::to_string(m.step_count() - 1));
  RenderPlan plan = make_render_plan(a.render, ds, {a.step});
  plan.request.step = a.step;
  FrameRenderer renderer(ds, plan.device);
  const double open_s = open_watch.seconds();

  FrameReport report;
  const std::clock_t cpu0 = std::clock();
  const Image img = renderer.render(plan.request, &report);
  const double cpu_s = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
  ImageWriteOptions wo;
  wo.alpha = a.render.alpha;
  wo.background = plan.background;
  write_image(img, a.output, wo);
  print_report(ds, plan.request, report, open_s, cpu_s, a.output);
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand(
      "render", "Render a dataset (or a built-in demo) to PNG or PFM: volume rendering and isosurfaces");
  cmd->add_option("dataset", a->dir, "dataset directory (or use --demo)");
  cmd->add_option("--demo", a->demo, "render a built-in demo instead (written to a temporary directory)")
      ->check(CLI::IsMember({"jet", "cosmo"}));
  cmd->add_option("--cells", a->cells, "demo size in cells")->capture_default_str();
  cmd->add_option("--step", a->step, "time step")->capture_default_str();
  add_render_options(cmd, a->render, RenderContext::image);
  cmd->add_option("-o,--output", a->output, "output image (.png or .pfm)")->required();
  cmd->callback([a] { run_render(*a); });
}

}  // namespace vs::cli
