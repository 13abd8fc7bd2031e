// play: stream a time series through the per-frame pipeline (read, upload, ranges, refit,
// render, output) at a chosen optimisation level, writing PNG frames or a video.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>

#include "commands.h"
#include "parse_util.h"
#include "render_options.h"
#include "volstream/backend/memory.h"
#include "volstream/core/error.h"
#include "volstream/core/progress.h"
#include "volstream/core/stopwatch.h"
#include "volstream/io/atomic_file.h"
#include "volstream/mpi/comm.h"
#include "volstream/stream/pipeline.h"
#include "volstream/stream/render_stages.h"
#include "volstream/stream/timeline.h"

namespace vs::cli {
namespace {
using namespace vs::stream;

struct PlayArgs {
  std::string dir, steps, pipeline = "overlap", timeline, output;
  int loop = 1;
  double fps = 24;
  bool quiet = false;
  RenderOptions render;  // shared with render and bench stream (render_options.h)
};

std::unique_ptr<FrameWriter> make_writer(const PlayArgs& a, const RenderPlan& r) {
  if (a.output.empty()) return nullptr;
  if (is_video_path(a.output))
    return std::make_unique<VideoWriter>(a.output, r.request.width, r.request.height, a.fps, r.background);
  return std::make_unique<PngSequenceWriter>(a.output, r.background);
}

// "12.3 frames/s, slowest: render 45.1 ms" from what the timeline holds so far.
std::string progress_detail(const Timeline& timeline, int frames, double seconds) {
  const StageSummary* slowest = nullptr;
  const auto summary = summarize(timeline.events());
  for (const StageSummary& s : summary)
    if (!slowest || s.mean_ms > slowest->mean_ms) slowest = &s;
  char text[128];
  std::snprintf(text, sizeof(text), "%.1f frames/s, slowest: %s %.1f ms", frames / std::max(seconds, 1e-9),
                slowest ? stage_name(slowest->stage) : "-", slowest ? slowest->mean_ms : 0.0);
  return text;
}

// The process's peak resident set: what a user compares with host memory for long series.
double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // KiB on Linux
}

void print_report(const Pipeline& p, const Timeline& timeline, const PlayStats& stats, const std::string& level) {
  std::printf("played %d frames at level %s in %.3f s: %.2f frames/s\n", stats.frames, level.c_str(), stats.seconds,
              stats.frames / std::max(stats.seconds, 1e-9));
  std::printf("buffers: %s\n", p.describe_buffers().c_str());
  std::printf("peak memory: %.1f MiB resident\n", peak_rss_mib());
  std::printf("memory: %s\n", format_memory(memory_ledger().snapshot()).c_str());
  if (!p.pin_failure().empty()) std::printf("staging not page-locked: %s\n", p.pin_failure().c_str());
  std::printf(
      "reads: %.1f MiB%s\n", double(stats.bytes_read) / (1 << 20),
      p.flags().direct_io ? (p.direct_io_active() ? ", O_DIRECT" : ", buffered (O_DIRECT refused)") : ", buffered");
  std::fputs(format_summary(summarize(timeline.events())).c_str(), stdout);
}

void run_play(const PlayArgs& a) {
  if (!a.timeline.empty()) check_output_directory(a.timeline);  // before the frames, not after
  const Dataset ds(a.dir);
  Level level;
  if (!parse_level(a.pipeline, level))
    throw UsageError("--pipeline: unknown level '" + a.pipeline + "' (" + level_names() + ")");
  if (a.loop < 1) throw UsageError("--loop must be at least 1");
  const std::vector<int> once = parse_steps(a.steps, ds.manifest().step_count());
  std::vector<int> steps;
  for (int i = 0; i < a.loop; ++i) steps.insert(steps.end(), once.begin(), once.end());

  const RenderPlan render = make_stream_render_plan(a.render, ds);
  std::unique_ptr<FrameWriter> writer = make_writer(a, render);
  RendererStages stages(ds, render.setup(), writer.get());
  Timeline timeline(std::string("play ") + level_name(level));
  Pipeline pipeline(ds, render.request.field, PipelineFlags::at(level), stages, &timeline);

  Progress progress("playing", steps.size(), !a.quiet, "frame");
  const Stopwatch playing;
  Stopwatch since_detail;
  auto on_frame = [&](int frame, int) {
    if (since_detail.seconds() > 0.25) {
      since_detail.lap();
      progress.set_detail(progress_detail(timeline, frame + 1, playing.seconds()));
    }
    progress.set(uint64_t(frame) + 1);
  };
  PlayStats stats;
  try {
    stats = pipeline.play(steps, on_frame);
    if (writer) writer->finish();
  } catch (...) {
    progress.fail();  // ends the bar at the frame that failed ("failed at frame 3/8"), never at 100%
    // The trace up to the failure is the most useful thing to look at then.
    if (!a.timeline.empty()) write_chrome_trace(a.timeline, {&timeline});
    throw;
  }
  progress.finish();
  if (!a.timeline.empty()) write_chrome_trace(a.timeline, {&timeline});
  print_report(pipeline, timeline, stats, a.pipeline);
}

}  // namespace

void add_play_command(CLI::App& app) {
  auto a = std::make_shared<PlayArgs>();
  auto* cmd = app.add_subcommand("play", "Stream and render a time series frame by frame (paper 000's pipeline)");
  cmd->add_option("dataset", a->dir, "dataset directory")->required();
  cmd->add_option("--steps", a->steps, "A:B[:S] (half-open, stride S) or a list 17,3,250 (default: all)");
  cmd->add_option("--pipeline", a->pipeline, "optimisation level: " + level_names())->capture_default_str();
  cmd->add_option("--timeline", a->timeline, "write the per-stage timeline as Chrome-trace JSON (Perfetto)");
  cmd->add_option("-o,--output", a->output, "frames_%04d.png (PNG sequence) or OUT.mp4 (via ffmpeg); default: none");
  cmd->add_option("--fps", a->fps, "video frame rate")->capture_default_str();
  cmd->add_option("--loop", a->loop, "play the steps N times")->capture_default_str();
  cmd->add_flag("-q,--quiet", a->quiet, "no progress bar");
  a->render = stream_render_defaults();
  add_render_options(cmd, a->render, RenderContext::stream);
  cmd->callback([a] {
    // Every rank would play the whole sequence; the data-parallel frame is `render`'s for now.
    if (mpi::size() > 1) throw UsageError("play does not split the data among MPI ranks yet (run it without mpirun)");
    run_play(*a);
  });
}

}  // namespace vs::cli
