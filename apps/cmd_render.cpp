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
#include "volstream/mpi/parallel_renderer.h"

namespace vs::cli {
namespace {

struct RenderArgs {
  std::string dir, demo, output;
  std::string composite = "auto";  // under mpirun
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

// The dataset, its temporary demo directory when there is one, and the frame's plan.
struct OpenedRender {
  std::unique_ptr<TempDemo> demo;
  std::unique_ptr<Dataset> dataset;
  RenderPlan plan;
};

// `load`: deferred under mpirun, where each rank reads only its share of a mesh's topology.
OpenedRender open_render(const RenderArgs& a, TopologyLoad load = TopologyLoad::whole) {
  if (a.dir.empty() == a.demo.empty()) throw UsageError("give either a dataset directory or --demo jet|cosmo");
  check_image_output(a.output);  // before the work, not after
  OpenedRender o;
  if (!a.demo.empty()) o.demo = std::make_unique<TempDemo>(a.demo, a.cells);
  o.dataset = std::make_unique<Dataset>(o.demo ? o.demo->dir.string() : a.dir, load);
  const DatasetManifest& m = o.dataset->manifest();
  if (a.step < 0 || a.step >= m.step_count())
    throw UsageError("step " + std::to_string(a.step) + " out of range 0.." + std::to_string(m.step_count() - 1));
  o.plan = make_render_plan(a.render, *o.dataset, {a.step});
  o.plan.request.step = a.step;
  return o;
}

void write_render(const Image& img, const RenderArgs& a, const RenderPlan& plan) {
  ImageWriteOptions wo;
  wo.alpha = a.render.alpha;
  wo.background = plan.background;
  write_image(img, a.output, wo);
}

mpi::CompositeScheme composite_scheme(const std::string& name) {
  if (name == "direct-send") return mpi::CompositeScheme::direct_send;
  if (name == "binary-swap") return mpi::CompositeScheme::binary_swap;
  return mpi::CompositeScheme::automatic;
}

// Rank 0's table: per rank what it holds and read, and its stages (the `composite` stage
// included), from the values every rank sent.
constexpr size_t kRankColumns = 14;
std::vector<double> rank_row(const mpi::ShareStats& share, uint64_t bytes_read, const FrameTimes& t,
                             const mpi::CompositeStats& c) {
  return {double(share.owned),
          double(share.held),
          double(bytes_read),
          t.read,
          t.ranges,
          t.classify + t.refit,
          t.render,
          c.seconds,
          double(c.bytes_sent),
          double(share.mesh ? share.vertices : share.bricks),
          double(share.mesh ? share.items : share.abrs),
          double(share.topology_bytes),
          double(share.topology_bytes_read),
          peak_rss_mib()};
}

// `total`: the dataset's cells or elements; `values`: its values per (field, step).
void print_ranks(const std::vector<double>& rows, const mpi::ShareStats& share, uint64_t total, uint64_t values,
                 const mpi::CompositeStats& c, bool compact) {
  const size_t n = rows.size() / kRankColumns;
  double read = 0, held = 0, sent = 0;
  const char* unit = share.mesh ? "elements" : "cells";
  const char* parts = share.mesh ? (compact ? "vertices, %.0f leaves" : "vertices, %.0f chunks") : "bricks, %.0f ABRs";
  for (size_t r = 0; r < n; ++r) {
    const double* v = rows.data() + r * kRankColumns;
    char held_parts[64];
    std::snprintf(held_parts, sizeof(held_parts), parts, v[10]);
    std::printf(
        "rank %zu: %s %.0f owned, %.0f held (%.0f %s), topology %.0f B, values read %.0f B, topology read %.0f B, "
        "peak RSS %.1f MiB; read %.4fs ranges %.4fs refit %.4fs render %.4fs composite %.4fs (sent %.0f B)\n",
        r, unit, v[0], v[1], v[9], held_parts, v[11], v[2], v[12], v[13], v[3], v[4], v[5], v[6], v[7], v[8]);
    read += v[2];
    held += v[1];
    sent += v[8];
  }
  const double bytes = double(values) * sizeof(float);
  std::printf("ranks %zu, composite %s: values read %.0f B for a %.0f B step (ghost overhead %+.1f%%), %.0f B sent\n",
              n, c.scheme == mpi::CompositeScheme::binary_swap ? "binary-swap" : "direct-send", read, bytes,
              100.0 * (held / double(total) - 1.0), sent);
}

// Under mpirun: every rank renders its region, the images are composited onto rank 0. Failures
// before the compositing are agreed on, so that no rank waits for one that gave up.
void run_render_ranks(const RenderArgs& a) {
  OpenedRender o;
  std::unique_ptr<mpi::ParallelRenderer> renderer;
  Image partial;
  FrameReport report;
  uint64_t total = 0, values = 0;
  mpi::agreed([&] {
    o = open_render(a, TopologyLoad::deferred);
    const DatasetManifest& m = o.dataset->manifest();
    total = o.dataset->is_mesh() ? m.mesh.elements : m.cell_count;
    values = m.value_count();
    renderer =
        std::make_unique<mpi::ParallelRenderer>(*o.dataset, o.plan.device, o.plan.request, mpi::rank(), mpi::size());
    partial = renderer->render_local(o.plan.request, &report);
  });
  mpi::CompositeStats composite;
  const Image img = renderer->composite(partial, o.plan.request, composite_scheme(a.composite), &composite);
  const std::vector<double> rows =
      mpi::gather(rank_row(renderer->share(), o.dataset->value_bytes_read(), report.seconds, composite));
  if (mpi::rank() != 0) return;
  write_render(img, a, o.plan);
  print_ranks(rows, renderer->share(), total, values, composite, o.dataset->is_compact_mesh());
  std::printf("render %ux%u on %d ranks -> %s\n", o.plan.request.width, o.plan.request.height, mpi::size(),
              a.output.c_str());
}

void run_render(const RenderArgs& a) {
  if (mpi::active()) return run_render_ranks(a);
  Stopwatch open_watch;
  const OpenedRender o = open_render(a);
  FrameRenderer renderer(*o.dataset, o.plan.device);
  const double open_s = open_watch.seconds();

  FrameReport report;
  const std::clock_t cpu0 = std::clock();
  const Image img = renderer.render(o.plan.request, &report);
  const double cpu_s = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
  write_render(img, a, o.plan);
  print_report(*o.dataset, o.plan.request, report, open_s, cpu_s, a.output);
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
  cmd->add_option("--composite", a->composite,
                  "under mpirun: how the ranks' images are blended (auto: binary-swap for a power-of-two "
                  "rank count, else direct-send)")
      ->check(CLI::IsMember({"auto", "direct-send", "binary-swap"}))
      ->capture_default_str();
  cmd->callback([a] { run_render(*a); });
}

}  // namespace vs::cli
