#include "volstream/stream/timeline.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "volstream/core/error.h"
#include "volstream/io/atomic_file.h"

namespace vs::stream {

namespace {
constexpr const char* kStageNames[kStageCount] = {"read", "upload", "ranges", "refit", "render", "composite", "output"};
}

const char* stage_name(Stage s) { return kStageNames[int(s)]; }

bool parse_stage(const std::string& name, Stage& out) {
  for (int i = 0; i < kStageCount; ++i)
    if (name == kStageNames[i]) {
      out = Stage(i);
      return true;
    }
  return false;
}

const char* lane_name(int lane) {
  switch (lane) {
    case kFrameLane:
      return "frame";
    case kPrefetchLane:
      return "prefetch";
    default:
      return "lane";
  }
}

Timeline::Timeline(std::string process, int pid) : process_(std::move(process)), pid_(pid), origin_(Clock::now()) {
  events_.reserve(1024);
}

void Timeline::record(Stage stage, int step, int lane, Clock::time_point begin, Clock::time_point end) {
  auto ns = [&](Clock::time_point t) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(t - origin_).count();
  };
  const TimelineEvent e{stage, step, lane, int64_t(ns(begin)), int64_t(ns(end))};
  std::lock_guard lock(mutex_);
  events_.push_back(e);
}

namespace {
std::vector<TimelineEvent> sorted_by_begin(std::vector<TimelineEvent> events) {
  std::stable_sort(events.begin(), events.end(), [](const auto& a, const auto& b) { return a.begin_ns < b.begin_ns; });
  return events;
}
}  // namespace

std::vector<TimelineEvent> Timeline::events() const {
  std::vector<TimelineEvent> copy;
  {
    std::lock_guard lock(mutex_);
    copy = events_;
  }
  return sorted_by_begin(std::move(copy));
}

std::vector<TimelineEvent> Timeline::take_events() {
  std::vector<TimelineEvent> taken;
  {
    std::lock_guard lock(mutex_);
    taken.swap(events_);
  }
  return sorted_by_begin(std::move(taken));
}

size_t Timeline::size() const {
  std::lock_guard lock(mutex_);
  return events_.size();
}

// ---------------------------------------------------------------------------------------------
nlohmann::json to_chrome_trace(const std::vector<const Timeline*>& timelines) {
  using json = nlohmann::json;
  json events = json::array();
  // All runs share the earliest origin so that runs recorded one after another line up in order.
  auto origin = timelines.empty() ? Timeline::Clock::time_point{} : timelines.front()->origin();
  for (const Timeline* t : timelines) origin = std::min(origin, t->origin());
  for (const Timeline* t : timelines) {
    const double shift_us = std::chrono::duration<double, std::micro>(t->origin() - origin).count();
    events.push_back({{"ph", "M"}, {"name", "process_name"}, {"pid", t->pid()}, {"args", {{"name", t->process()}}}});
    events.push_back(
        {{"ph", "M"}, {"name", "process_sort_index"}, {"pid", t->pid()}, {"args", {{"sort_index", t->pid()}}}});
    std::vector<int> lanes;
    for (const TimelineEvent& e : t->events()) {
      events.push_back({{"ph", "X"},
                        {"name", stage_name(e.stage)},
                        {"cat", "stream"},
                        {"ts", shift_us + double(e.begin_ns) * 1e-3},
                        {"dur", double(e.end_ns - e.begin_ns) * 1e-3},
                        {"pid", t->pid()},
                        {"tid", e.lane},
                        {"args", {{"step", e.step}}}});
      if (std::find(lanes.begin(), lanes.end(), e.lane) == lanes.end()) lanes.push_back(e.lane);
    }
    for (int lane : lanes)
      events.push_back({{"ph", "M"},
                        {"name", "thread_name"},
                        {"pid", t->pid()},
                        {"tid", lane},
                        {"args", {{"name", lane_name(lane)}}}});
  }
  return {{"traceEvents", std::move(events)}, {"displayTimeUnit", "ms"}};
}

void write_chrome_trace(const std::filesystem::path& path, const std::vector<const Timeline*>& timelines) {
  AtomicFile out(path);
  out.write(to_chrome_trace(timelines).dump(1) + "\n");
  out.commit();
}

// ---------------------------------------------------------------------------------------------
std::vector<StageSummary> summarize(const std::vector<TimelineEvent>& events) {
  std::vector<std::vector<double>> ms(kStageCount);
  for (const TimelineEvent& e : events) ms[size_t(e.stage)].push_back(e.ms());
  std::vector<StageSummary> out;
  for (int s = 0; s < kStageCount; ++s) {
    auto& v = ms[size_t(s)];
    if (v.empty()) continue;
    std::sort(v.begin(), v.end());
    StageSummary sum{Stage(s)};
    sum.count = v.size();
    for (double x : v) sum.total_ms += x;
    sum.mean_ms = sum.total_ms / double(v.size());
    const size_t mid = v.size() / 2;
    sum.median_ms = v.size() % 2 ? v[mid] : 0.5 * (v[mid - 1] + v[mid]);
    sum.max_ms = v.back();
    out.push_back(sum);
  }
  return out;
}

const StageSummary* slowest_stage(const std::vector<StageSummary>& summary) {
  const StageSummary* slowest = nullptr;
  for (const StageSummary& s : summary)
    if (!slowest || s.mean_ms > slowest->mean_ms) slowest = &s;
  return slowest;
}

std::string format_summary(const std::vector<StageSummary>& summary) {
  std::string text = "stage      count    total ms     mean ms   median ms      max ms\n";
  char line[160];
  for (const StageSummary& s : summary) {
    std::snprintf(line, sizeof(line), "%-8s %7zu %11.2f %11.3f %11.3f %11.3f\n", stage_name(s.stage), s.count,
                  s.total_ms, s.mean_ms, s.median_ms, s.max_ms);
    text += line;
  }
  return text;
}

}  // namespace vs::stream
