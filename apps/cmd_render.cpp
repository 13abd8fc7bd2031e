// render: one image of a dataset (or a built-in demo): DVR and/or isosurfaces through the ABRs.
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "render_blocks.h"
#include "render_options.h"
#include "volstream/amr/demo.h"
#include "volstream/core/error.h"
#include "volstream/cuda/backend.h"
#include "volstream/io/atomic_file.h"
#include "volstream/io/cleanup.h"
#include "volstream/io/dataset.h"
#include "volstream/io/image.h"
#include "volstream/amr/ranges.h"
#include "volstream/render/renderer.h"

namespace vs::cli {
namespace {

struct RenderArgs {
  std::string dir, demo, output;
  double cells = 1e6;
  int step = 0;
  RenderOptions render;     // shared with play and bench stream (render_options.h)
  BlockRenderArgs blocks;   // --integrator, --optics, ... (cmd_render_blocks.cpp)
};

// A demo written to a fresh private directory (mkdtemp: never a planted path or link), removed
// again on exit and on Ctrl-C.
struct TempDemo {
  std::filesystem::path root, dir;
  std::unique_ptr<RemoveOnSignal> on_signal;
  TempDemo(const std::string& name, double cells) {
    std::string path = (std::filesystem::temp_directory_path() / ("volstream_render_" + name + "_XXXXXX")).string();
    if (!::mkdtemp(path.data())) input_error(path, std::string("cannot create a temporary directory: ") + std::strerror(errno));
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

void run_render(RenderArgs a) {
  if (a.dir.empty() == a.demo.empty()) throw UsageError("give either a dataset directory or --demo jet|cosmo");
  check_image_output(a.output);  // before the work, not after
  std::unique_ptr<TempDemo> demo;
  auto t_load = std::chrono::steady_clock::now();
  if (!a.demo.empty()) demo = std::make_unique<TempDemo>(a.demo, a.cells);
  const std::string dir = demo ? demo->dir.string() : a.dir;
  const Dataset ds(dir);
  const DatasetManifest& m = ds.manifest();
  if (a.step < 0 || a.step >= m.step_count())
    throw UsageError("step " + std::to_string(a.step) + " out of range 0.." + std::to_string(m.step_count() - 1));
  const RenderOptions& o = a.render;
  const RenderPlan plan = make_render_plan(o, ds, {a.step});
  const int field = plan.field;
  const TransferFunctionSpec& spec = plan.setup.tf;
  const TransferTable tf(spec);
  const FrameSettings& fs = plan.setup.settings;
  const Device device = plan.setup.device;

  const std::vector<float> values = ds.load_values(field, a.step);
  // Computed here by default: datasets converted before the ranges became tight store per-brick ones.
  const auto t_ranges = std::chrono::steady_clock::now();
  const std::vector<Range> abr_ranges = o.stored_ranges ? ds.load_abr_ranges(field, a.step)
                                                        : compute_abr_ranges(ds.topology(), values.data(), nullptr,
                                                                             fs.brick_ranges ? RangeMode::per_brick : RangeMode::tight);
  const double ranges_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_ranges).count();
  std::vector<float> color_values;
  std::unique_ptr<TransferTable> color_tf;
  if (plan.color_field >= 0) {
    color_values = ds.load_values(plan.color_field, a.step);
    color_tf = std::make_unique<TransferTable>(plan.color_tf);
  }
  const double load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count();

  AmrRenderer renderer(ds.topology(), m.transform);
  FrameStats stats;
  renderer.classify(abr_ranges, tf, fs.integrator, fs.skip, &stats);
  const Camera& camera = plan.setup.camera;
  a.blocks.device = device;  // the block raycaster renders on --device too
  const std::clock_t cpu0 = std::clock();
  const Image img = a.blocks.enabled()
                        ? render_with_blocks(ds, a.step, field, tf, camera, fs, a.blocks, &stats)
                        : renderer.render(device, values.data(), tf, color_tf ? color_values.data() : nullptr,
                                          color_tf.get(), camera, fs, &stats);
  const double cpu_s = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
  ImageWriteOptions wo;
  wo.alpha = o.alpha;
  wo.background = plan.background;
  write_image(img, a.output, wo);

  const std::string dev = device == Device::cuda ? "cuda (" + cuda::device_name() + ")" : "cpu";
  std::printf("device: %s\n", dev.c_str());
  std::printf("field %s step %d, range [%g, %g]%s, %llu of %zu ABRs visible%s\n", m.fields[size_t(field)].name.c_str(),
              a.step, spec.lo, spec.hi, spec.log_scale ? " (log)" : "", (unsigned long long)stats.visible_abrs,
              ds.topology().abrs.size(), fs.skip ? "" : " (no skipping)");
  std::printf("load %.3fs, ranges %.4fs%s, classify %.4fs, refit %.4fs%s\n", load_s - ranges_s, ranges_s,
              o.stored_ranges ? " (stored)" : "", stats.classify_seconds, stats.refit_seconds,
              device == Device::cuda ? (", upload " + std::to_string(stats.upload_seconds) + "s").c_str() : "");
  std::printf("render %ux%u: %.3fs (%.3fs CPU time), %.1f M samples, %.1f M samples/s -> %s\n", fs.width, fs.height,
              stats.render_seconds, cpu_s, stats.samples * 1e-6, stats.samples * 1e-6 / std::max(stats.render_seconds, 1e-9),
              a.output.c_str());
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand("render", "Render a dataset (or a built-in demo) to PNG or PFM: volume rendering and isosurfaces");
  cmd->add_option("dataset", a->dir, "dataset directory (or use --demo)");
  cmd->add_option("--demo", a->demo, "render a built-in demo instead (written to a temporary directory)")
      ->check(CLI::IsMember({"jet", "cosmo"}));
  cmd->add_option("--cells", a->cells, "demo size in cells")->capture_default_str();
  cmd->add_option("--step", a->step, "time step")->capture_default_str();
  add_render_options(cmd, a->render, RenderContext::image);
  cmd->add_option("-o,--output", a->output, "output image (.png or .pfm)")->required();
  add_block_render_options(cmd, a->blocks);
  cmd->callback([a] { run_render(*a); });
}

}  // namespace vs::cli
