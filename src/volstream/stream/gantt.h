// Reads a Chrome trace (as written by the timeline) and draws it as an SVG Gantt chart in the
// manner of paper 000, Fig. 3: one row per lane (or per stage), bars coloured by stage and labelled
// with their step, a time axis with ticks, and a legend.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace vs::stream {

// One complete ("ph":"X") event of a trace, with its process and thread names resolved.
struct TraceEvent {
  std::string name;  // the stage
  int step = -1;     // args.step; -1 when absent
  int pid = 0, tid = 0;
  std::string process, thread;
  double ts_us = 0, dur_us = 0;
};

// Accepts {"traceEvents": [...]} or a bare array. Throws InputError(path) on bad JSON, events
// with missing or non-finite times, or a trace without complete events.
std::vector<TraceEvent> read_chrome_trace(const std::filesystem::path& path);

struct GanttOptions {
  enum class Rows { lane, stage } rows = Rows::lane;
  int width = 1200;  // pixels
  // Start every process (run, e.g. pipeline level) at time 0, so that runs recorded one after
  // another share one time axis and compare at a glance, as the panels of Fig. 3 do.
  bool align_processes = true;
  std::string title;
};
std::string gantt_svg(const std::vector<TraceEvent>& events, const GanttOptions& options);

}  // namespace vs::stream
