// The streaming pipeline (paper 000, section 5): timeline, Chrome trace and Gantt chart, the step
// reader, and the pipeline at every level: same frames, overlap where promised, jumps, and
// mid-stream errors.
#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <thread>

#include "test_util.h"
#include "volstream/amr/demo.h"
#include "volstream/amr/ranges.h"
#include "volstream/core/error.h"
#include "volstream/cuda/backend.h"
#include "volstream/stream/gantt.h"
#include "volstream/stream/pipeline.h"
#include "volstream/stream/render_stages.h"
#include "volstream/stream/step_reader.h"
#include "volstream/stream/timeline.h"

namespace vs::stream {
namespace {
namespace fs = std::filesystem;

constexpr int kSteps = 5;

// One small time series (the demo jet, about 10^4 cells) per test process: ctest runs tests in
// parallel processes, so the directory is private to this one and removed at exit.
// With file_order, the same series also gets file-order copies (same demo, same device order).
struct Series {
  fs::path dir;
  explicit Series(bool file_order)
      : dir(fs::temp_directory_path() / "volstream_tests" /
            ((file_order ? "stream_file_order_" : "stream_series_") + std::to_string(::getpid()))) {
    fs::remove_all(dir);
    auto source = make_demo({"jet", 10000, kSteps});
    ConvertOptions options;
    options.quiet = true;
    options.file_order = file_order;
    convert_to_dataset(*source, dir, options);
  }
  ~Series() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

const fs::path& series_dir() {
  static const Series series(false);
  return series.dir;
}

// A copy of the series whose step 2 (field 0) is damaged by `damage`.
fs::path damaged_copy(const std::string& name, const std::function<void(const fs::path&, uint64_t)>& damage) {
  const fs::path dir = test::scratch_dir(name);
  fs::copy(series_dir(), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  const Dataset ds(dir);
  damage(ds.values_path(0, 2), ds.manifest().cell_count * 4);
  return dir;
}

// A render stage that only checksums the values and ranges. With `await_reads_in`, rendering
// step t waits (up to 2 s) until that timeline holds a read of step t+1: a prefetching pipeline
// gets there during the frame, so the test does not depend on how fast threads are scheduled.
class ChecksumStages : public FrameStages {
 public:
  explicit ChecksumStages(const AmrTopology& topology, const Timeline* await_reads_in = nullptr)
      : topology_(topology), count_(topology.cell_count), await_(await_reads_in) {}
  void ranges(const FrameData& f) override { ranges_sum_ = sum_ranges(compute_abr_ranges(topology_, f.values)); }
  void refit(const FrameData&, bool rebuild) override { rebuilds += rebuild ? 1 : 0; }
  void render(const FrameData& f) override {
    uint64_t h = 1469598103934665603ull;
    const auto* bytes = reinterpret_cast<const uint8_t*>(f.values);
    for (uint64_t i = 0; i < count_ * 4; ++i) h = (h ^ bytes[i]) * 1099511628211ull;
    uint64_t ranges_bits;
    std::memcpy(&ranges_bits, &ranges_sum_, sizeof(ranges_bits));
    hash_ = h ^ ranges_bits;
    if (await_ && f.step + 1 < kSteps) await_read(f.step + 1);
  }
  void output(const FrameData& f) override { frames.emplace_back(f.step, hash_); }
  std::vector<std::pair<int, uint64_t>> frames;  // (step, checksum) per output frame
  int rebuilds = 0;

 private:
  static double sum_ranges(const std::vector<Range>& ranges) {
    double s = 0;
    for (const Range& r : ranges) s += r.lo <= r.hi ? double(r.lo) + r.hi : 0.0;
    return s;
  }
  void await_read(int step) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (std::chrono::steady_clock::now() < deadline) {
      for (const TimelineEvent& e : await_->events())
        if (e.stage == Stage::read && e.step == step) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  const AmrTopology& topology_;
  uint64_t count_;
  const Timeline* await_;
  uint64_t hash_ = 0;
  double ranges_sum_ = 0;
};

std::vector<int> all_steps() {
  std::vector<int> s(kSteps);
  std::iota(s.begin(), s.end(), 0);
  return s;
}

// ---------------------------------------------------------------------------------------------
TEST(Timeline, ConcurrentAppendsAllArrive) {
  Timeline t;
  std::vector<std::thread> threads;
  for (int lane = 0; lane < 4; ++lane)
    threads.emplace_back([&t, lane] {
      for (int i = 0; i < 500; ++i) {
        const auto now = Timeline::Clock::now();
        t.record(Stage(i % kStageCount), i, lane, now, now + std::chrono::microseconds(i));
      }
    });
  for (auto& th : threads) th.join();
  const auto events = t.events();
  ASSERT_EQ(events.size(), 2000u);
  EXPECT_TRUE(std::is_sorted(events.begin(), events.end(), [](auto& a, auto& b) { return a.begin_ns < b.begin_ns; }));
}

TEST(Timeline, SummaryCountsTotalsMeansMedians) {
  Timeline t;
  const auto o = t.origin();
  using std::chrono::milliseconds;
  for (int ms : {1, 2, 6}) t.record(Stage::read, 0, 0, o, o + milliseconds(ms));
  for (int ms : {4, 8}) t.record(Stage::render, 0, 0, o, o + milliseconds(ms));
  const auto sum = summarize(t.events());
  ASSERT_EQ(sum.size(), 2u);
  EXPECT_EQ(sum[0].stage, Stage::read);
  EXPECT_EQ(sum[0].count, 3u);
  EXPECT_NEAR(sum[0].total_ms, 9, 1e-9);
  EXPECT_NEAR(sum[0].mean_ms, 3, 1e-9);
  EXPECT_NEAR(sum[0].median_ms, 2, 1e-9);
  EXPECT_NEAR(sum[1].median_ms, 6, 1e-9);
  EXPECT_NE(format_summary(sum).find("render"), std::string::npos);
}

TEST(Timeline, WritesAValidChromeTrace) {
  Timeline a("baseline", 1), b("overlap", 2);
  Timeline::Scope(&a, Stage::read, 7, kFrameLane);
  Timeline::Scope(&b, Stage::upload, 8, kPrefetchLane);
  const fs::path path = test::scratch_dir("trace") / "t.json";
  write_chrome_trace(path, {&a, &b});
  std::ifstream in(path);
  const auto doc = nlohmann::json::parse(in);
  ASSERT_TRUE(doc.at("traceEvents").is_array());
  int complete = 0;
  for (const auto& e : doc["traceEvents"]) {
    ASSERT_TRUE(e.contains("ph") && e.contains("pid"));
    if (e["ph"] != "X") continue;
    ++complete;
    Stage s;
    EXPECT_TRUE(parse_stage(e.at("name").get<std::string>(), s));
    EXPECT_TRUE(e.at("ts").is_number());
    EXPECT_GE(e.at("dur").get<double>(), 0);
    EXPECT_TRUE(e.at("tid").is_number_integer());
    EXPECT_TRUE(e.at("args").at("step").is_number_integer());
  }
  EXPECT_EQ(complete, 2);
  const auto events = read_chrome_trace(path);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].process, "baseline");
  EXPECT_EQ(events[1].thread, "prefetch");
  EXPECT_EQ(events[1].step, 8);
}

TEST(Gantt, DrawsOneBarPerEventWithAxisAndLegend) {
  std::vector<TraceEvent> events;
  for (int i = 0; i < kStageCount; ++i)
    events.push_back({stage_name(Stage(i)), i, 1, i % 2, "run", "lane", 1000.0 * i, 900});
  const std::string svg = gantt_svg(events, {});
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  size_t bars = 0;
  for (size_t p = svg.find("<title>"); p != std::string::npos; p = svg.find("<title>", p + 1)) ++bars;
  EXPECT_EQ(bars, events.size());
  for (int i = 0; i < kStageCount; ++i)
    EXPECT_NE(svg.find(std::string(">") + stage_name(Stage(i)) + "<"), std::string::npos);
  EXPECT_NE(svg.find("time [ms]"), std::string::npos);
}

TEST(Gantt, BadTracesAreInputErrors) {
  const fs::path dir = test::scratch_dir("bad_trace");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"garbage.json", "{not json"},
      {"empty.json", "{\"traceEvents\": []}"},
      {"nots.json", "[{\"ph\": \"X\", \"name\": \"read\", \"dur\": 1}]"},
      {"negative.json", "[{\"ph\": \"X\", \"name\": \"read\", \"ts\": 0, \"dur\": -1}]"},
      {"scalar.json", "42"}};
  for (const auto& [name, text] : cases) {
    std::ofstream(dir / name) << text;
    try {
      read_chrome_trace(dir / name);
      ADD_FAILURE() << name << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), (dir / name).string());
    }
  }
  EXPECT_THROW(read_chrome_trace(dir / "missing.json"), InputError);
}

// ---------------------------------------------------------------------------------------------
TEST(StepReader, BufferedAndDirectReadTheStoredValues) {
  const Dataset ds(series_dir());
  const uint64_t n = ds.manifest().cell_count;
  const std::vector<float> expected = ds.load_values(1, 3);
  for (ReadMode mode : {ReadMode::buffered, ReadMode::direct}) {
    StepReader reader(n, mode);
    HostBuffer buffer(reader.padded_bytes(), mode == ReadMode::direct);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(buffer.data()) % kIoAlignment, 0u);
    EXPECT_EQ(buffer.bytes() % kIoAlignment, 0u);
    reader.read(ds.values_path(1, 3), 3, buffer.data());
    EXPECT_EQ(std::memcmp(buffer.data(), expected.data(), n * 4), 0);
    EXPECT_GE(reader.bytes_read(), n * 4);
  }
}

TEST(StepReader, AcceptsFilesWithoutPadding) {
  const fs::path dir = damaged_copy("unpadded", [](const fs::path& f, uint64_t bytes) { fs::resize_file(f, bytes); });
  const Dataset ds(dir);
  const uint64_t n = ds.manifest().cell_count;
  ASSERT_NE(n * 4 % kIoAlignment, 0u);
  const std::vector<float> expected = ds.load_values(0, 2);
  StepReader reader(n, ReadMode::direct);
  HostBuffer buffer(reader.padded_bytes(), false);
  reader.read(ds.values_path(0, 2), 2, buffer.data());
  EXPECT_EQ(std::memcmp(buffer.data(), expected.data(), n * 4), 0);
  EXPECT_TRUE(reader.direct());  // no fallback to buffered reads was needed
}

TEST(StepReader, MissingTruncatedOrWronglySizedFilesNameTheStep) {
  const std::map<std::string, std::function<void(const fs::path&, uint64_t)>> damages = {
      {"missing", [](const fs::path& f, uint64_t) { fs::remove(f); }},
      {"truncated", [](const fs::path& f, uint64_t bytes) { fs::resize_file(f, bytes - 4); }},
      {"wrong size", [](const fs::path& f, uint64_t) { fs::resize_file(f, fs::file_size(f) + kIoAlignment); }}};
  for (const auto& [what, damage] : damages) {
    const fs::path dir = damaged_copy("reader_" + what.substr(0, 5), damage);
    const Dataset ds(dir);
    for (ReadMode mode : {ReadMode::buffered, ReadMode::direct}) {
      StepReader reader(ds.manifest().cell_count, mode);
      HostBuffer buffer(reader.padded_bytes(), false);
      try {
        reader.read(ds.values_path(0, 2), 2, buffer.data());
        ADD_FAILURE() << what << " file accepted";
      } catch (const InputError& e) {
        EXPECT_EQ(e.file(), ds.values_path(0, 2).string());
        EXPECT_NE(std::string(e.what()).find("step 2"), std::string::npos) << e.what();
        const std::string word = what == "missing" ? "missing" : what;
        EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
      }
    }
  }
}

TEST(StepReader, EvictionLeavesTheFileOutOfThePageCache) {
  const Dataset ds(series_dir());
  const fs::path f = ds.values_path(0, 0);
  (void)ds.load_values(0, 0);
  ASSERT_TRUE(evict_from_page_cache(f));
  const double resident = page_cache_resident_fraction(f);
  if (resident < 0) GTEST_SKIP() << "mincore not available";
  EXPECT_LT(resident, 0.5);  // a few pages may be pulled back in by readahead elsewhere
}

// ---------------------------------------------------------------------------------------------
TEST(Pipeline, LevelsAreCumulativeAndBuffersFixed) {
  const Dataset ds(series_dir());
  for (int l = 0; l < kLevelCount; ++l) {
    const PipelineFlags f = PipelineFlags::at(Level(l));
    EXPECT_EQ(f.async_io, l >= 1);
    EXPECT_EQ(f.overlap, l == kLevelCount - 1);
    Level parsed;
    ASSERT_TRUE(parse_level(level_name(Level(l)), parsed));
    EXPECT_EQ(parsed, Level(l));
    ChecksumStages stages(ds.topology());
    Pipeline p(ds, 0, f, stages, nullptr);
    const uint64_t before = p.buffer_bytes();
    p.play(all_steps());
    p.play(all_steps());
    EXPECT_EQ(p.buffer_bytes(), before);  // memory does not grow with the number of steps
    EXPECT_EQ(stages.rebuilds, f.refit ? 0 : 2 * kSteps);
  }
}

RenderSetup small_render_setup(const Dataset& ds, Device device) {
  RenderSetup setup;
  setup.tf.colors = builtin_color_map("viridis");
  setup.tf.opacity = default_opacity_ramp();
  const Range r = ds.manifest().fields[0].step_ranges[0];
  setup.tf.lo = r.lo;
  setup.tf.hi = r.hi;
  setup.settings.width = 32;
  setup.settings.height = 24;
  setup.settings.integrator.ref_step = 0;
  const AmrRenderer bounds(ds.topology(), ds.manifest().transform);
  setup.camera = default_camera(bounds.world_bounds(), 32.0 / 24.0);
  setup.device = device;
  return setup;
}

// images[level][step]: every step played at every pipeline level.
using LevelImages = std::vector<std::map<int, std::vector<float>>>;
LevelImages play_every_level(const Dataset& ds, const RenderSetup& setup) {
  LevelImages images(kLevelCount);
  for (int l = 0; l < kLevelCount; ++l) {
    RendererStages stages(ds, setup, nullptr);
    stages.on_image = [&](const FrameData& f, const Image& img) { images[size_t(l)][f.step] = img.rgba; };
    Pipeline(ds, 0, PipelineFlags::at(Level(l)), stages, nullptr).play(all_steps());
    EXPECT_EQ(images[size_t(l)].size(), size_t(kSteps)) << level_name(Level(l));
  }
  return images;
}

TEST(Pipeline, EveryLevelRendersIdenticalFrames) {
  const Dataset ds(series_dir());
  const LevelImages images = play_every_level(ds, small_render_setup(ds, Device::cpu));
  for (int l = 1; l < kLevelCount; ++l)
    for (int step = 0; step < kSteps; ++step)
      EXPECT_EQ(images[size_t(l)].at(step), images[0].at(step)) << level_name(Level(l)) << " step " << step;
  // Something was drawn, and the steps differ (the data moves).
  const auto& first = images[0].at(0);
  EXPECT_NE(first, std::vector<float>(first.size(), 0.f));
  EXPECT_NE(first, images[0].at(kSteps - 1));
}

// Per-brick ranges cull fewer ABRs but, being conservative too, draw the same frames.
TEST(Pipeline, BrickRangesDrawTheSameFrames) {
  const Dataset ds(series_dir());
  RenderSetup setup = small_render_setup(ds, Device::cpu);
  setup.tf.lo = setup.tf.hi - 0.2f * (setup.tf.hi - setup.tf.lo);  // selective: only the highest values opaque
  std::map<int, std::vector<float>> tight, per_brick;
  uint64_t visible_tight = 0, visible_brick = 0;
  for (bool brick : {false, true}) {
    setup.settings.brick_ranges = brick;
    RendererStages stages(ds, setup, nullptr);
    stages.on_image = [&](const FrameData& f, const Image& img) {
      (brick ? per_brick : tight)[f.step] = img.rgba;
      (brick ? visible_brick : visible_tight) += stages.visible_abrs();
    };
    Pipeline(ds, 0, PipelineFlags::at(Level::overlap), stages, nullptr).play(all_steps());
  }
  EXPECT_EQ(tight, per_brick);
  EXPECT_LT(visible_tight, visible_brick);
}

// The GPU-resident frame: ranges, classification and refit on the device equal the host's
// exactly (same functions, min/max only); images equal across levels exactly and equal the CPU
// images within the tolerance of Render.CudaEqualsCpu.
TEST(PipelineCuda, DeviceRangesAndRefitEqualTheHost) {
  if (!cuda::cuda_available()) GTEST_SKIP() << "no CUDA device";
  const Dataset ds(series_dir());
  const std::vector<float> values = ds.load_values(0, 1);
  const RenderSetup setup = small_render_setup(ds, Device::cuda);
  const TransferTable tf(setup.tf);
  AmrRenderer host(ds.topology(), ds.manifest().transform);
  const std::vector<Range> ranges = compute_abr_ranges(ds.topology(), values.data());
  const uint64_t host_visible = host.classify(ranges, tf, setup.settings.integrator, true);

  cuda::DeviceScene scene(ds.topology());
  scene.set_bvh(host.template_bvh().nodes);
  cuda::DeviceValueBuffers device_values(1, values.size());
  device_values.upload(0, values.data(), values.size());
  scene.compute_ranges(device_values.data(0));
  const std::vector<Range> device_ranges = scene.download_ranges();
  ASSERT_EQ(device_ranges.size(), ranges.size());
  for (size_t i = 0; i < ranges.size(); ++i) {
    ASSERT_EQ(device_ranges[i].lo, ranges[i].lo) << "ABR " << i;
    ASSERT_EQ(device_ranges[i].hi, ranges[i].hi) << "ABR " << i;
  }
  EXPECT_EQ(scene.classify_and_refit(tf, setup.settings.integrator, true), host_visible);
  const std::vector<BvhNode> nodes = scene.download_refit_nodes();
  ASSERT_EQ(nodes.size(), host.refit_nodes().size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    const box3f a = nodes[i].box, b = host.refit_nodes()[i].box;
    ASSERT_TRUE(a.lower == b.lower && a.upper == b.upper) << "node " << i;
  }
}

TEST(PipelineCuda, EveryLevelOnTheGpuMatchesTheCpu) {
  if (!cuda::cuda_available()) GTEST_SKIP() << "no CUDA device";
  const Dataset ds(series_dir());
  const LevelImages cpu = play_every_level(ds, small_render_setup(ds, Device::cpu));
  const LevelImages gpu = play_every_level(ds, small_render_setup(ds, Device::cuda));
  for (int step = 0; step < kSteps; ++step) {
    for (int l = 1; l < kLevelCount; ++l)
      EXPECT_EQ(gpu[size_t(l)].at(step), gpu[0].at(step)) << level_name(Level(l)) << " step " << step;
    const std::vector<float>&a = cpu[0].at(step), &b = gpu[0].at(step);
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += std::abs(double(a[i]) - double(b[i]));
    EXPECT_LT(sum / double(a.size()), 1e-3) << "step " << step;
  }
}

TEST(Pipeline, ReadOfTheNextStepOverlapsProcessingOnlyWhenAsync) {
  const Dataset ds(series_dir());
  for (Level level : {Level::baseline, Level::async_io, Level::direct_io, Level::overlap}) {
    Timeline timeline(level_name(level));
    const bool async = level != Level::baseline;
    ChecksumStages stages(ds.topology(), async ? &timeline : nullptr);
    Pipeline(ds, 0, PipelineFlags::at(level), stages, &timeline).play(all_steps());
    // The read of t+1 overlaps the processing of t when it starts before t's output has ended
    // (at the baseline it can only start after).
    std::map<int, int64_t> read_begin, processing_end;
    for (const TimelineEvent& e : timeline.events()) {
      if (e.stage == Stage::read) read_begin[e.step] = e.begin_ns;
      if (e.stage == Stage::output) processing_end[e.step] = e.end_ns;
    }
    int overlapped = 0;
    for (int t = 0; t + 1 < kSteps; ++t) overlapped += read_begin.at(t + 1) < processing_end.at(t);
    EXPECT_EQ(overlapped, async ? kSteps - 1 : 0) << level_name(level);
    // The overlap level also uploads on the loader; the others upload on the frame thread.
    for (const TimelineEvent& e : timeline.events())
      if (e.stage == Stage::upload && e.step > 0) {
        EXPECT_EQ(e.lane, level == Level::overlap ? kPrefetchLane : kFrameLane) << level_name(level);
      }
  }
}

TEST(Pipeline, JumpsCostOneLoadAndMatchSequentialPlay) {
  const Dataset ds(series_dir());
  ChecksumStages sequential(ds.topology());
  Pipeline(ds, 0, PipelineFlags::at(Level::overlap), sequential, nullptr).play(all_steps());
  const std::map<int, uint64_t> by_step(sequential.frames.begin(), sequential.frames.end());
  for (Level level : {Level::baseline, Level::overlap}) {
    ChecksumStages jumps(ds.topology());
    Timeline timeline;
    const std::vector<int> order = {3, 0, 4, 4, 1};
    Pipeline(ds, 0, PipelineFlags::at(level), jumps, &timeline).play(order);
    ASSERT_EQ(jumps.frames.size(), order.size());
    for (size_t i = 0; i < order.size(); ++i) {
      EXPECT_EQ(jumps.frames[i].first, order[i]);
      EXPECT_EQ(jumps.frames[i].second, by_step.at(order[i])) << "step " << order[i];
    }
    const auto events = timeline.events();
    const auto reads =
        std::count_if(events.begin(), events.end(), [](const TimelineEvent& e) { return e.stage == Stage::read; });
    EXPECT_EQ(size_t(reads), order.size());
  }
}

// Frame by frame (the viewer's play): a step that was the previous call's `next` comes from the
// loader, any other one (a seek) is loaded then; either way the frame is that step's.
TEST(Pipeline, AdvanceFrameByFrameWithSeeks) {
  const Dataset ds(series_dir());
  ChecksumStages sequential(ds.topology());
  Pipeline(ds, 0, PipelineFlags::at(Level::baseline), sequential, nullptr).play(all_steps());
  const std::map<int, uint64_t> by_step(sequential.frames.begin(), sequential.frames.end());
  // (step, next): two guesses of `next` are wrong (the frames after them seek), the last one is
  // never asked for.
  const std::vector<std::pair<int, int>> calls = {{0, 1}, {1, 2}, {4, 0}, {0, 1}, {3, 4}, {4, -1}, {2, 3}, {3, 4}};
  for (int l = 0; l < kLevelCount; ++l) {
    ChecksumStages stages(ds.topology());
    Timeline timeline;
    {
      Pipeline p(ds, 0, PipelineFlags::at(Level(l)), stages, &timeline);
      for (size_t i = 0; i < calls.size(); ++i) p.advance(int(i), calls[i].first, calls[i].second);
    }  // waits for the loader's last read
    ASSERT_EQ(stages.frames.size(), calls.size());
    for (size_t i = 0; i < calls.size(); ++i) {
      EXPECT_EQ(stages.frames[i].first, calls[i].first);
      EXPECT_EQ(stages.frames[i].second, by_step.at(calls[i].first)) << level_name(Level(l)) << " frame " << i;
    }
    const auto events = timeline.events();
    const auto reads =
        std::count_if(events.begin(), events.end(), [](const TimelineEvent& e) { return e.stage == Stage::read; });
    // Every frame reads once; a prefetching level also reads each wrong guess and the last `next`.
    EXPECT_EQ(size_t(reads), calls.size() + (l >= int(Level::async_io) ? 3 : 0)) << level_name(Level(l));
  }
}

// A prefetched step that is not asked for after all does not fail the frame with its error;
// asking for it does.
TEST(Pipeline, AdvanceDropsTheErrorOfAStepNotAskedFor) {
  const fs::path dir = damaged_copy("pipeline_advance", [](const fs::path& f, uint64_t) { fs::remove(f); });
  const Dataset ds(dir);
  for (Level level : {Level::async_io, Level::overlap}) {
    ChecksumStages stages(ds.topology());
    Pipeline p(ds, 0, PipelineFlags::at(level), stages, nullptr);
    p.advance(0, 1, 2);  // the loader fails on step 2
    p.advance(1, 3, 2);  // ... and again
    EXPECT_THROW(p.advance(2, 2, -1), InputError) << level_name(level);
    p.advance(3, 4, -1);
    EXPECT_EQ(stages.frames.size(), 3u);
  }
}

// The viewer changes the view between frames: the stages render what set_request says, the same
// image as the frame renderer's.
TEST(Pipeline, RendererStagesFollowTheRequest) {
  const Dataset ds(series_dir());
  const RenderSetup setup = small_render_setup(ds, Device::cpu);
  RendererStages stages(ds, setup, nullptr);
  std::vector<std::vector<float>> images;
  stages.on_image = [&](const FrameData&, const Image& img) { images.push_back(img.rgba); };
  Pipeline p(ds, 0, PipelineFlags::at(Level::overlap), stages, nullptr);
  FrameRenderer reference(ds, Device::cpu);
  FrameRequest r;
  r.tf = setup.tf;
  r.camera = setup.camera;
  r.width = setup.settings.width;
  r.height = setup.settings.height;
  for (int frame = 0; frame < 3; ++frame) {
    r.step = frame + 1;
    r.camera.position = r.camera.position + 0.3 * (r.camera.position - r.camera.look_at);  // zoom out
    r.tf.hi = setup.tf.hi - 0.1f * float(frame) * (setup.tf.hi - setup.tf.lo);
    stages.set_request(r);
    p.advance(frame, r.step, r.step + 1);
    EXPECT_EQ(images.back(), reference.render(r).rgba) << "frame " << frame;
  }
  EXPECT_NE(images[0], images[1]);
  r.second_field = 0;
  EXPECT_THROW(stages.set_request(r), UsageError);
  r.second_field = -1;
  r.stored_ranges = true;
  EXPECT_THROW(stages.set_request(r), UsageError);
}

TEST(Pipeline, MidStreamErrorsNameTheStepAndStopBeforeItsFrame) {
  const std::map<std::string, std::function<void(const fs::path&, uint64_t)>> damages = {
      {"missing", [](const fs::path& f, uint64_t) { fs::remove(f); }},
      {"truncated", [](const fs::path& f, uint64_t bytes) { fs::resize_file(f, bytes / 2); }},
      {"wrong size", [](const fs::path& f, uint64_t) { fs::resize_file(f, fs::file_size(f) + 3 * kIoAlignment); }}};
  for (const auto& [what, damage] : damages) {
    const fs::path dir = damaged_copy("pipeline_" + what.substr(0, 5), damage);
    const Dataset ds(dir);
    for (int l = 0; l < kLevelCount; ++l) {
      ChecksumStages stages(ds.topology());
      try {
        Pipeline(ds, 0, PipelineFlags::at(Level(l)), stages, nullptr).play(all_steps());
        ADD_FAILURE() << what << " step file accepted at " << level_name(Level(l));
      } catch (const InputError& e) {
        EXPECT_EQ(e.file(), ds.values_path(0, 2).string());
        EXPECT_NE(std::string(e.what()).find("step 2"), std::string::npos) << e.what();
      }
      ASSERT_EQ(stages.frames.size(), 2u) << what << " at " << level_name(Level(l));
      EXPECT_EQ(stages.frames[1].first, 1);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// File-order copies (convert/demo --file-order): the levels before `preordered` read each step in
// the generator's cell order and gather it into device order through the real permutation.

const fs::path& file_order_series_dir() {
  static const Series series(true);
  return series.dir;
}

// A copy of `from` in a scratch directory named `name`; `edit` then damages it.
fs::path edited_copy(const fs::path& from, const std::string& name, const std::function<void(const fs::path&)>& edit) {
  const fs::path dir = test::scratch_dir(name);
  fs::copy(from, dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  edit(dir);
  return dir;
}

TEST(FileOrder, IndexIsAPermutationAndNotTheIdentity) {
  const Dataset plain(series_dir()), ds(file_order_series_dir());
  EXPECT_FALSE(plain.has_file_order());
  EXPECT_THROW(plain.load_file_index(), InputError);
  ASSERT_TRUE(ds.has_file_order());
  const std::vector<uint32_t> index = ds.load_file_index();
  ASSERT_EQ(index.size(), ds.manifest().cell_count);
  std::vector<uint32_t> sorted = index;
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i) << "not a permutation";
  size_t moved = 0;
  for (size_t i = 0; i < index.size(); ++i) moved += index[i] != i;
  EXPECT_GT(moved, index.size() / 2) << "the demo's cell order is almost the device order: " << moved << " of "
                                     << index.size() << " cells move";
}

TEST(FileOrder, FileOrderFilesAreTheDeviceOrderFilesPermuted) {
  const Dataset plain(series_dir()), ds(file_order_series_dir());
  const uint64_t n = ds.manifest().cell_count;
  const std::vector<uint32_t> index = ds.load_file_index();
  auto source = make_demo({"jet", 10000, kSteps});
  ASSERT_EQ(source->cell_count(), n);
  // The index maps every device cell to its position in the generator's cell list.
  const std::vector<Cell> input_cells = source->take_cells(), device_cells = ds.load_cells();
  for (uint64_t i = 0; i < n; ++i) {
    const Cell &a = device_cells[i], &b = input_cells[index[i]];
    ASSERT_TRUE(a.lower == b.lower && a.level == b.level) << "device cell " << i;
  }
  std::vector<float> input(n);
  for (int field = 0; field < int(ds.manifest().fields.size()); ++field)
    for (int step = 0; step < kSteps; ++step) {
      const std::vector<float> device = ds.load_values(field, step), file = ds.load_file_order_values(field, step);
      // The file-order copy is the generator's output as it came, padded like the device-order file.
      source->read_values(field, step, input.data());
      ASSERT_EQ(std::memcmp(file.data(), input.data(), n * 4), 0) << "field " << field << " step " << step;
      EXPECT_EQ(fs::file_size(ds.file_order_values_path(field, step)), align_up(n * 4));
      // device[i] == file[index[i]], bit for bit; and the device-order files are those of a
      // dataset converted without file order.
      for (uint64_t i = 0; i < n; ++i)
        ASSERT_EQ(std::memcmp(&device[i], &file[index[i]], 4), 0)
            << "field " << field << " step " << step << " cell " << i;
      const std::vector<float> without = plain.load_values(field, step);
      ASSERT_EQ(std::memcmp(device.data(), without.data(), n * 4), 0) << "field " << field << " step " << step;
    }
}

TEST(FileOrder, EveryLevelRendersTheFramesOfTheDeviceOrderSeries) {
  const Dataset plain(series_dir()), ds(file_order_series_dir());
  // Which flatten each level runs, visible to reports (bench stream).
  for (int l = 0; l < kLevelCount; ++l) {
    const bool flattens = l < int(Level::preordered);
    ChecksumStages a(plain.topology()), b(ds.topology());
    Pipeline p(plain, 0, PipelineFlags::at(Level(l)), a, nullptr), q(ds, 0, PipelineFlags::at(Level(l)), b, nullptr);
    EXPECT_EQ(p.flatten_is_identity(), flattens) << level_name(Level(l));
    EXPECT_FALSE(q.flatten_is_identity()) << level_name(Level(l));
    EXPECT_STREQ(p.flatten_mode(), flattens ? "identity" : "none");
    EXPECT_STREQ(q.flatten_mode(), flattens ? "file-order" : "none");
    EXPECT_EQ(p.buffer_bytes(), q.buffer_bytes());
  }
  const LevelImages device_order = play_every_level(plain, small_render_setup(plain, Device::cpu));
  const LevelImages file_order = play_every_level(ds, small_render_setup(ds, Device::cpu));
  for (int l = 0; l < kLevelCount; ++l)
    for (int step = 0; step < kSteps; ++step)
      EXPECT_EQ(file_order[size_t(l)].at(step), device_order[0].at(step)) << level_name(Level(l)) << " step " << step;
  EXPECT_NE(file_order[0].at(0), file_order[0].at(kSteps - 1));
}

TEST(FileOrder, DamagedFileOrderStepsNameTheStepBeforePreordered) {
  const std::map<std::string, std::function<void(const fs::path&, uint64_t)>> damages = {
      {"missing", [](const fs::path& f, uint64_t) { fs::remove(f); }},
      {"truncated", [](const fs::path& f, uint64_t bytes) { fs::resize_file(f, bytes / 2); }},
      {"wrong size", [](const fs::path& f, uint64_t) { fs::resize_file(f, fs::file_size(f) + 3 * kIoAlignment); }}};
  for (const auto& entry : damages) {
    const std::string& what = entry.first;  // not a structured binding: clang's lambdas cannot capture those
    const auto& damage = entry.second;
    const fs::path dir =
        edited_copy(file_order_series_dir(), "file_order_" + what.substr(0, 5), [&](const fs::path& d) {
          const Dataset ds(d);
          damage(ds.file_order_values_path(0, 2), ds.manifest().cell_count * 4);
        });
    const Dataset ds(dir);
    for (int l = 0; l < kLevelCount; ++l) {
      ChecksumStages stages(ds.topology());
      if (l >= int(Level::preordered)) {  // reads the intact device-order files
        Pipeline(ds, 0, PipelineFlags::at(Level(l)), stages, nullptr).play(all_steps());
        EXPECT_EQ(stages.frames.size(), size_t(kSteps)) << what << " at " << level_name(Level(l));
        continue;
      }
      try {
        Pipeline(ds, 0, PipelineFlags::at(Level(l)), stages, nullptr).play(all_steps());
        ADD_FAILURE() << what << " file-order step accepted at " << level_name(Level(l));
      } catch (const InputError& e) {
        EXPECT_EQ(e.file(), ds.file_order_values_path(0, 2).string());
        EXPECT_NE(std::string(e.what()).find("step 2"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      }
      ASSERT_EQ(stages.frames.size(), 2u) << what << " at " << level_name(Level(l));
      EXPECT_EQ(stages.frames[1].first, 1);
    }
  }
}

TEST(FileOrder, OldManifestsAndBadIndexFiles) {
  // A manifest written before the key existed reads as "no file-order copies".
  const fs::path old = edited_copy(series_dir(), "file_order_old", [](const fs::path& d) {
    std::ifstream in(d / "manifest.json");
    auto manifest = nlohmann::json::parse(in);
    ASSERT_TRUE(manifest.contains("file_order"));
    manifest.erase("file_order");
    std::ofstream(d / "manifest.json") << manifest.dump(1);
  });
  const Dataset ds(old);
  EXPECT_FALSE(ds.has_file_order());
  ChecksumStages stages(ds.topology());
  EXPECT_TRUE(Pipeline(ds, 0, PipelineFlags::at(Level::baseline), stages, nullptr).flatten_is_identity());

  // An index that is missing, of the wrong size or not a permutation is an InputError naming it.
  const fs::path missing = edited_copy(file_order_series_dir(), "file_order_noindex",
                                       [](const fs::path& d) { fs::remove(d / dataset_files::kFileIndex); });
  try {
    const Dataset bad(missing);
    ADD_FAILURE() << "dataset without its file index opened";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (missing / dataset_files::kFileIndex).string());
  }
  const fs::path short_index = edited_copy(file_order_series_dir(), "file_order_short", [](const fs::path& d) {
    fs::resize_file(d / dataset_files::kFileIndex, fs::file_size(d / dataset_files::kFileIndex) - 4);
  });
  EXPECT_THROW(Dataset{short_index}, InputError);
  const fs::path repeated = edited_copy(file_order_series_dir(), "file_order_repeat", [](const fs::path& d) {
    std::fstream f(d / dataset_files::kFileIndex, std::ios::in | std::ios::out | std::ios::binary);
    uint32_t first = 0;
    f.read(reinterpret_cast<char*>(&first), 4);
    f.seekp(4);
    f.write(reinterpret_cast<const char*>(&first), 4);  // entry 1 repeats entry 0
  });
  const Dataset bad(repeated);
  ChecksumStages bad_stages(bad.topology());
  try {
    Pipeline(bad, 0, PipelineFlags::at(Level::baseline), bad_stages, nullptr);
    ADD_FAILURE() << "a file index that is not a permutation was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (repeated / dataset_files::kFileIndex).string());
    EXPECT_NE(std::string(e.what()).find("not a permutation"), std::string::npos) << e.what();
  }
  Pipeline(bad, 0, PipelineFlags::at(Level::preordered), bad_stages, nullptr).play({0});  // does not need it
}

TEST(FrameWriters, PngPatternsAreValidated) {
  EXPECT_EQ(PngSequenceWriter::format("f_%04d.png", 7), "f_0007.png");
  EXPECT_EQ(PngSequenceWriter::format("100%%_%d.png", 12), "100%_12.png");
  EXPECT_EQ(PngSequenceWriter::format("%3d.png", 5), "  5.png");
  for (const char* bad : {"frames.png", "%s.png", "%d_%d.png", "%x.png", "%"})
    EXPECT_THROW(PngSequenceWriter(bad, {}), UsageError) << bad;
  EXPECT_TRUE(is_video_path("a/b.mp4"));
  EXPECT_FALSE(is_video_path("a/b_%04d.png"));
}

}  // namespace
}  // namespace vs::stream
