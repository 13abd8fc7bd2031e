// The timeline: begin/end of every stage of every frame, on host steady clocks, from any thread.
// It is what `play` and `bench stream` report from, and it writes Chrome-trace JSON (open it in
// Perfetto or chrome://tracing; `volstream timeline` draws it as an SVG Gantt chart).
#pragma once
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace vs::stream {

// The per-frame stages of DESIGN.md, in pipeline order (composite: under mpirun, the ranks'
// partial images blended onto rank 0).
enum class Stage : uint8_t { read, upload, ranges, refit, render, composite, output };
inline constexpr int kStageCount = 7;
const char* stage_name(Stage s);
// The stage called `name`; false if there is none.
bool parse_stage(const std::string& name, Stage& out);

// Lanes are the threads (or, on a GPU, streams) a stage ran on; each becomes one Chrome-trace tid.
inline constexpr int kFrameLane = 0;     // the thread that drives the frames
inline constexpr int kPrefetchLane = 1;  // the background loader of the next step
const char* lane_name(int lane);

struct TimelineEvent {
  Stage stage;
  int step;
  int lane;
  int64_t begin_ns, end_ns;  // since the timeline's origin
  double ms() const { return double(end_ns - begin_ns) * 1e-6; }
};

class Timeline {
 public:
  using Clock = std::chrono::steady_clock;

  // `process` names the run (e.g. the pipeline level); it becomes the trace's process name.
  explicit Timeline(std::string process = "volstream", int pid = 1);
  Timeline(const Timeline&) = delete;
  Timeline& operator=(const Timeline&) = delete;

  // Thread-safe: stages on different threads append concurrently.
  void record(Stage stage, int step, int lane, Clock::time_point begin, Clock::time_point end);

  // Records [construction, destruction) of a scope.
  class Scope {
   public:
    Scope(Timeline* t, Stage s, int step, int lane) : t_(t), s_(s), step_(step), lane_(lane), begin_(Clock::now()) {}
    ~Scope() {
      if (t_) t_->record(s_, step_, lane_, begin_, Clock::now());
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    Timeline* t_;
    Stage s_;
    int step_, lane_;
    Clock::time_point begin_;
  };
  Scope scope(Stage s, int step, int lane) { return Scope(this, s, step, lane); }

  std::vector<TimelineEvent> events() const;  // a snapshot, sorted by begin
  // The events so far, sorted by begin, and forgotten: a long run (the viewer's play) reads them
  // as they come instead of keeping them all.
  std::vector<TimelineEvent> take_events();
  size_t size() const;
  const std::string& process() const { return process_; }
  int pid() const { return pid_; }
  Clock::time_point origin() const { return origin_; }

 private:
  std::string process_;
  int pid_;
  Clock::time_point origin_;
  mutable std::mutex mutex_;
  std::vector<TimelineEvent> events_;
};

// Chrome trace ("traceEvents": complete events "ph":"X" with "ts"/"dur" in microseconds,
// "name" = stage, "args": {"step": t}, "pid" = run, "tid" = lane; plus process/thread names).
// Several timelines (e.g. one per pipeline level) share one file as separate processes.
nlohmann::json to_chrome_trace(const std::vector<const Timeline*>& timelines);
void write_chrome_trace(const std::filesystem::path& path, const std::vector<const Timeline*>& timelines);

// Per-stage statistics over all events of that stage.
struct StageSummary {
  Stage stage;
  size_t count = 0;
  double total_ms = 0, mean_ms = 0, median_ms = 0, max_ms = 0;
};
std::vector<StageSummary> summarize(const std::vector<TimelineEvent>& events);  // stages that occurred
// The stage with the longest mean time (null for an empty summary): what limits the frame rate.
const StageSummary* slowest_stage(const std::vector<StageSummary>& summary);
std::string format_summary(const std::vector<StageSummary>& summary);  // a text table

}  // namespace vs::stream
