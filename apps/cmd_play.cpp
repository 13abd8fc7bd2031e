// play: stream a time series through the per-frame pipeline (read, upload, ranges, refit,
// render, output) at a chosen optimisation level, writing PNG frames or a video.
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
#include "volstream/mpi/parallel_renderer.h"
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
  const auto summary = summarize(timeline.events());
  const StageSummary* slowest = slowest_stage(summary);
  char text[128];
  std::snprintf(text, sizeof(text), "%.1f frames/s, slowest: %s %.1f ms", frames / std::max(seconds, 1e-9),
                slowest ? stage_name(slowest->stage) : "-", slowest ? slowest->mean_ms : 0.0);
  return text;
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

// ---- Under mpirun (issue 17) ----------------------------------------------------------------
// Each rank renders its kd region of every step (reading only its share of the values), the
// partial images are composited onto rank 0, which writes the frames. The frames follow one
// another (no overlap of one step's reading with the previous one's rendering yet). Every rank's
// stages, composite included, go into one trace on rank 0, one process per rank.

// The stages FrameRenderer ran for a frame, laid end to end from `start` (it runs them one after
// another and reports their durations).
void record_frame(Timeline& t, const FrameTimes& s, int step, Timeline::Clock::time_point start) {
  const std::pair<Stage, double> stages[] = {{Stage::read, s.read},
                                             {Stage::upload, s.upload},
                                             {Stage::ranges, s.ranges},
                                             {Stage::refit, s.classify + s.refit},
                                             {Stage::render, s.render}};
  for (const auto& [stage, seconds] : stages) {
    const auto end =
        start + std::chrono::duration_cast<Timeline::Clock::duration>(std::chrono::duration<double>(seconds));
    t.record(stage, step, kFrameLane, start, end);
    start = end;
  }
}

// Every rank's timeline on rank 0 (empty elsewhere), as processes "rank R". Events travel as
// five doubles with absolute steady-clock times: one clock for the ranks of one node (ranks on
// other nodes keep their own offsets). `per_rank` events at most (the rest padded with stage -1).
std::vector<std::unique_ptr<Timeline>> gather_timelines(const Timeline& mine, size_t per_rank) {
  using namespace std::chrono;
  const auto origin_ns = double(duration_cast<nanoseconds>(mine.origin().time_since_epoch()).count());
  std::vector<double> flat(per_rank * 5, -1.0);
  const std::vector<TimelineEvent> events = mine.events();
  for (size_t i = 0; i < std::min(per_rank, events.size()); ++i) {
    const TimelineEvent& e = events[i];
    const double row[5] = {double(e.stage), double(e.step), double(e.lane), origin_ns + double(e.begin_ns),
                           origin_ns + double(e.end_ns)};
    std::copy(row, row + 5, flat.begin() + ptrdiff_t(5 * i));
  }
  const std::vector<double> all = mpi::gather(flat);
  std::vector<std::unique_ptr<Timeline>> out;
  const auto at = [](double ns) { return Timeline::Clock::time_point(nanoseconds(int64_t(ns))); };
  for (size_t r = 0; r * flat.size() < all.size(); ++r) {
    out.push_back(std::make_unique<Timeline>("rank " + std::to_string(r), int(r) + 1));
    for (size_t i = 0; i < per_rank; ++i) {
      const double* row = all.data() + r * flat.size() + 5 * i;
      if (row[0] >= 0) out.back()->record(Stage(int(row[0])), int(row[1]), int(row[2]), at(row[3]), at(row[4]));
    }
  }
  return out;
}

// Mean milliseconds per frame of each stage, one line per rank.
void print_rank_stages(const std::vector<std::unique_ptr<Timeline>>& timelines, int frames) {
  std::printf("mean ms per frame    read  ranges   refit  render composite  output\n");
  const Stage shown[] = {Stage::read, Stage::ranges, Stage::refit, Stage::render, Stage::composite, Stage::output};
  for (const auto& t : timelines) {
    double ms[kStageCount] = {};
    for (const TimelineEvent& e : t->events()) ms[int(e.stage)] += e.ms();
    std::printf("%-18s", t->process().c_str());
    for (const Stage s : shown) std::printf(" %7.2f", ms[int(s)] / std::max(frames, 1));
    std::printf("\n");
  }
}

void run_play_ranks(const PlayArgs& a) {
  if (!a.timeline.empty() && mpi::rank() == 0) check_output_directory(a.timeline);
  std::unique_ptr<Dataset> ds;
  RenderPlan plan;
  std::vector<int> steps;
  std::unique_ptr<mpi::ParallelRenderer> renderer;
  std::unique_ptr<FrameWriter> writer;
  mpi::agreed([&] {
    ds = std::make_unique<Dataset>(a.dir, TopologyLoad::deferred);  // each rank reads its share
    if (a.loop < 1) throw UsageError("--loop must be at least 1");
    const std::vector<int> once = parse_steps(a.steps, ds->manifest().step_count());
    for (int i = 0; i < a.loop; ++i) steps.insert(steps.end(), once.begin(), once.end());
    plan = make_stream_render_plan(a.render, *ds);
    renderer = std::make_unique<mpi::ParallelRenderer>(*ds, plan.device, plan.request, mpi::rank(), mpi::size());
    if (mpi::rank() == 0) writer = make_writer(a, plan);
  });
  Timeline timeline("rank " + std::to_string(mpi::rank()), mpi::rank() + 1);
  Progress progress("playing", steps.size(), !a.quiet && mpi::rank() == 0, "frame");
  const Stopwatch playing;
  for (size_t frame = 0; frame < steps.size(); ++frame) {
    const int step = steps[frame];
    plan.request.step = step;
    Image partial;
    mpi::agreed([&] {
      FrameReport report;
      const auto start = Timeline::Clock::now();
      partial = renderer->render_local(plan.request, &report);
      record_frame(timeline, report.seconds, step, start);
    });
    Image image;
    {
      const auto scope = timeline.scope(Stage::composite, step, kFrameLane);
      image = renderer->composite(partial, plan.request, mpi::CompositeScheme::automatic);
    }
    mpi::agreed([&] {
      if (!writer) return;
      const auto scope = timeline.scope(Stage::output, step, kFrameLane);
      writer->write(image, int(frame), step);
    });
    progress.set(frame + 1);
  }
  mpi::agreed([&] {
    if (writer) writer->finish();
  });
  progress.finish();
  const double seconds = playing.seconds();
  const auto timelines = gather_timelines(timeline, steps.size() * (kStageCount + 1));
  if (mpi::rank() != 0) return;
  std::printf("played %zu frames on %d ranks in %.3f s: %.2f frames/s\n", steps.size(), mpi::size(), seconds,
              double(steps.size()) / std::max(seconds, 1e-9));
  print_rank_stages(timelines, int(steps.size()));
  if (!a.timeline.empty()) {
    std::vector<const Timeline*> all;
    for (const auto& t : timelines) all.push_back(t.get());
    write_chrome_trace(a.timeline, all);
  }
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
  cmd->callback([a] { mpi::active() ? run_play_ranks(*a) : run_play(*a); });
}

}  // namespace vs::cli
