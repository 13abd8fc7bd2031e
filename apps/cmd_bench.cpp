// bench: benchmark drivers, one subcommand each. `bench stream` runs every pipeline level of
// paper 000 (Fig. 3) over the same steps and prints ms per stage, frame time, frames/s, speed-up
// over the baseline and the read bandwidth next to the disk's raw sequential O_DIRECT bandwidth.
#include <chrono>
#include <cstdio>
#include <set>
#include <sstream>

#include "commands.h"
#include "parse_util.h"
#include "render_options.h"
#include "volstream/core/error.h"
#include "volstream/core/stopwatch.h"
#include "volstream/stream/pipeline.h"
#include "volstream/stream/render_stages.h"
#include "volstream/stream/step_reader.h"
#include "volstream/stream/timeline.h"

namespace vs::cli {
namespace {
using namespace vs::stream;

struct BenchStreamArgs {
  std::string dir, steps, levels, timeline;
  bool keep_cache = false;
  RenderOptions render;  // shared with render and play (render_options.h)
};

// The output stage of a benchmark: the 8-bit conversion a video writer would do, no disk writes.
// Also hashes each frame, so that the levels can be checked to render the same images.
class HashingSink : public FrameWriter {
 public:
  explicit HashingSink(vec3f background) : background_(background) {}
  void write(const Image& image, int, int step) override {
    const std::vector<uint8_t> rgb = to_rgb8(image, background_);
    uint64_t h = 1469598103934665603ull;  // FNV-1a
    for (uint8_t b : rgb) h = (h ^ b) * 1099511628211ull;
    hashes.emplace_back(step, h);
  }
  std::vector<std::pair<int, uint64_t>> hashes;

 private:
  vec3f background_;
};

struct CacheState {
  bool evicted = true;  // posix_fadvise succeeded on every file
  double resident = 0;  // mean fraction of the files' pages still cached afterwards (-1: unknown)
};

// Drops the files from the page cache (unprivileged, clean pages only) and checks with mincore.
CacheState drop_cache(const std::vector<std::filesystem::path>& files) {
  CacheState c;
  double sum = 0;
  for (const auto& f : files) {
    c.evicted = evict_from_page_cache(f) && c.evicted;
    const double r = page_cache_resident_fraction(f);
    if (r < 0) sum = -1e30;
    sum += r;
  }
  c.resident = files.empty() || sum < 0 ? -1 : sum / double(files.size());
  return c;
}

// Plain sequential O_DIRECT reads of the same files into one aligned buffer: the disk's bandwidth.
double raw_read_gbps(const Dataset& ds, const std::vector<std::filesystem::path>& files, bool& direct) {
  StepReader reader(ds.manifest().value_count(), ReadMode::direct);
  HostBuffer buffer(reader.padded_bytes(), false);
  const Stopwatch watch;
  for (size_t i = 0; i < files.size(); ++i) reader.read(files[i], int(i), buffer.data());
  const double s = watch.seconds();
  direct = reader.direct();
  return double(reader.bytes_read()) / std::max(s, 1e-9) * 1e-9;
}

struct LevelResult {
  Level level;
  PlayStats stats;
  double stage_ms[kStageCount] = {};  // mean per frame
  double read_total_ms = 0;
  std::vector<std::pair<int, uint64_t>> frame_hashes;  // (step, hash of the 8-bit frame)
  CacheState cache;
};

std::vector<Level> parse_levels(const std::string& text) {
  std::vector<Level> levels;
  if (text.empty()) {
    for (int l = 0; l < kLevelCount; ++l) levels.push_back(Level(l));
    return levels;
  }
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    Level l;
    if (!parse_level(item, l)) throw UsageError("--levels: unknown level '" + item + "' (" + level_names() + ")");
    levels.push_back(l);
  }
  return levels;
}

LevelResult run_level(const Dataset& ds, const RenderPlan& r, const std::vector<int>& steps, Level level,
                      Timeline& timeline, const std::vector<std::filesystem::path>& files, bool keep_cache) {
  LevelResult res;
  res.level = level;
  if (!keep_cache) res.cache = drop_cache(files);
  HashingSink sink(r.background);
  RendererStages stages(ds, r.setup(), &sink);
  Pipeline pipeline(ds, r.request.field, PipelineFlags::at(level), stages, &timeline);
  res.stats = pipeline.play(steps);
  for (const StageSummary& s : summarize(timeline.events())) {
    res.stage_ms[int(s.stage)] = s.total_ms / std::max(res.stats.frames, 1);
    if (s.stage == Stage::read) res.read_total_ms = s.total_ms;
  }
  res.frame_hashes = std::move(sink.hashes);
  return res;
}

void print_table(const std::vector<LevelResult>& results) {
  std::printf("\n%-11s %8s %8s %8s %8s %8s %8s %10s %9s %9s %10s\n", "level", "read", "upload", "ranges", "refit",
              "render", "output", "frame ms", "frames/s", "speed-up", "read GB/s");
  const double base_frame = results.front().stats.seconds / std::max(results.front().stats.frames, 1);
  for (const LevelResult& r : results) {
    const double frame_ms = 1e3 * r.stats.seconds / std::max(r.stats.frames, 1);
    std::printf("%-11s", level_name(r.level));
    for (double ms : r.stage_ms) std::printf(" %8.2f", ms);
    std::printf(" %10.2f %9.2f %8.2fx %10.2f\n", frame_ms, 1e3 / frame_ms, 1e3 * base_frame / frame_ms,
                double(r.stats.bytes_read) / std::max(r.read_total_ms * 1e-3, 1e-12) * 1e-9);
  }
  std::printf(
      "(stage columns: mean ms per frame on any thread; from async-io on, read (and from overlap on, upload)\n"
      " run on the loader thread, hidden behind the frame; frame ms = wall time / frames)\n");
}

void run_bench_stream(const BenchStreamArgs& a) {
  const Dataset ds(a.dir);
  const std::vector<int> steps = parse_steps(a.steps, ds.manifest().step_count());
  const std::vector<Level> levels = parse_levels(a.levels);
  const RenderPlan r = make_stream_render_plan(a.render, ds);
  std::vector<std::filesystem::path> files;
  for (int s : std::set<int>(steps.begin(), steps.end())) {
    files.push_back(ds.values_path(r.request.field, s));
    if (ds.has_file_order())
      files.push_back(ds.file_order_values_path(r.request.field, s));  // the baseline levels read these
  }

  const stream::RenderSetup setup = r.setup();
  const auto& fs = setup.settings;
  std::printf("bench stream: %s, field %s, %zu frames, %ux%u on %s, %.1f MiB per step\n", a.dir.c_str(),
              ds.manifest().fields[size_t(r.request.field)].name.c_str(), steps.size(), fs.width, fs.height,
              to_string(setup.device), double(ds.manifest().value_count()) * 4 / (1 << 20));
  const CacheState before = drop_cache(files);
  bool direct = false;
  const double raw = raw_read_gbps(ds, files, direct);
  std::printf("raw disk bandwidth (plain sequential %s read, cache dropped): %.2f GB/s\n",
              direct ? "O_DIRECT" : "buffered", raw);
  if (a.keep_cache)
    std::printf("page cache: kept (--keep-cache)\n");
  else
    std::printf("page cache: dropped before each level with posix_fadvise(DONTNEED) per file%s; resident after: %s\n",
                before.evicted ? "" : " (refused for some files)",
                before.resident < 0 ? "unknown" : (std::to_string(int(before.resident * 100 + 0.5)) + "%").c_str());

  std::printf("flatten before preordered: %s\n",
              ds.has_file_order() ? "gather from the file-order copy through file_index.bin"
                                  : "identity gather (no file-order copy: demo/convert --file-order writes one)");
  {  // warm-up: thread pool, page tables and caches of the topology, off the record
    HashingSink sink(r.background);
    RendererStages stages(ds, r.setup(), &sink);
    Pipeline(ds, r.request.field, PipelineFlags::at(Level::baseline), stages, nullptr).play({steps.front()});
  }
  std::vector<std::unique_ptr<Timeline>> timelines;
  std::vector<LevelResult> results;
  for (Level level : levels) {
    timelines.push_back(std::make_unique<Timeline>(level_name(level), int(level) + 1));
    results.push_back(run_level(ds, r, steps, level, *timelines.back(), files, a.keep_cache));
    std::fprintf(stderr, "  %-11s %.2f frames/s\n", level_name(level),
                 results.back().stats.frames / results.back().stats.seconds);
  }
  print_table(results);
  bool identical = true;
  for (const LevelResult& res : results) identical = identical && res.frame_hashes == results.front().frame_hashes;
  std::printf("frames identical at every level: %s\n", identical ? "yes" : "NO");
  if (!a.timeline.empty()) {
    std::vector<const Timeline*> list;
    for (const auto& t : timelines) list.push_back(t.get());
    write_chrome_trace(a.timeline, list);
    std::printf("timeline: %s (volstream timeline %s -o chart.svg)\n", a.timeline.c_str(), a.timeline.c_str());
  }
  if (!identical) throw std::runtime_error("the levels rendered different frames");
}

void add_bench_stream(CLI::App& bench) {
  auto a = std::make_shared<BenchStreamArgs>();
  auto* cmd = bench.add_subcommand("stream", "Every pipeline level over the same steps: paper 000, Fig. 3 as a table");
  cmd->add_option("dataset", a->dir, "dataset directory")->required();
  cmd->add_option("--steps", a->steps, "A:B[:S] or a list (default: all)");
  cmd->add_option("--levels", a->levels, "comma-separated levels (default: all, in order)");
  cmd->add_option("--timeline", a->timeline, "write all levels' timelines (one process each) as Chrome-trace JSON");
  cmd->add_flag("--keep-cache", a->keep_cache, "do not drop the files from the page cache between levels");
  a->render = stream_render_defaults();
  add_render_options(cmd, a->render, RenderContext::stream);
  cmd->callback([a] { run_bench_stream(*a); });
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Benchmarks (one subcommand each)");
  bench->require_subcommand(1);
  add_bench_stream(*bench);
  add_bench_integrators(*bench);  // cmd_bench_integrators.cpp
  // Further benchmarks register here.
}

}  // namespace vs::cli
