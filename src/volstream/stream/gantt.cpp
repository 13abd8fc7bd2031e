#include "volstream/stream/gantt.h"

#include "volstream/core/xml.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"
#include "volstream/stream/timeline.h"

namespace vs::stream {
namespace {
using json = nlohmann::json;
constexpr double kMaxTraceMicroseconds = 1e15;
constexpr size_t kMaxRows = 10000;  // rows of a chart (lanes or stage names per process)

double finite_number(const json& e, const char* key) {
  const auto it = e.find(key);
  if (it == e.end() || !it->is_number())
    throw std::runtime_error(std::string("event without a numeric \"") + key + "\"");
  const double v = it->get<double>();
  // Microseconds; 1e15 is 31 years. Beyond it spans overflow to inf and the axis never ends.
  if (!(std::fabs(v) <= kMaxTraceMicroseconds))
    throw std::runtime_error(std::string("\"") + key + "\" not a number within +-1e15");
  return v;
}

int int_or(const json& e, const char* key, int fallback) {
  const auto it = e.find(key);
  return it != e.end() && it->is_number_integer() ? it->get<int>() : fallback;
}

// Names given by metadata events ("process_name", "thread_name").
struct Names {
  std::map<int, std::string> process;
  std::map<std::pair<int, int>, std::string> thread;
};

void read_metadata(const json& e, Names& names) {
  const std::string what = e.value("name", "");
  const auto args = e.find("args");
  if (args == e.end() || !args->is_object() || !args->contains("name") || !(*args)["name"].is_string()) return;
  const std::string name = (*args)["name"].get<std::string>();
  if (what == "process_name") names.process[int_or(e, "pid", 0)] = name;
  if (what == "thread_name") names.thread[{int_or(e, "pid", 0), int_or(e, "tid", 0)}] = name;
}

TraceEvent read_complete(const json& e) {
  TraceEvent t;
  if (!e.contains("name") || !e["name"].is_string()) throw std::runtime_error("event without a \"name\"");
  t.name = e["name"].get<std::string>();
  t.ts_us = finite_number(e, "ts");
  t.dur_us = finite_number(e, "dur");
  if (t.dur_us < 0) throw std::runtime_error("event with a negative \"dur\"");
  t.pid = int_or(e, "pid", 0);
  t.tid = int_or(e, "tid", 0);
  const auto args = e.find("args");
  if (args != e.end() && args->is_object()) t.step = int_or(*args, "step", -1);
  return t;
}

std::vector<TraceEvent> parse_trace(const json& doc) {
  const json* list = &doc;
  if (doc.is_object()) {
    if (!doc.contains("traceEvents")) throw std::runtime_error("no \"traceEvents\"");
    list = &doc["traceEvents"];
  }
  if (!list->is_array()) throw std::runtime_error("\"traceEvents\" is not an array");
  Names names;
  std::vector<TraceEvent> out;
  for (const json& e : *list) {
    if (!e.is_object()) throw std::runtime_error("an event is not an object");
    const std::string ph = e.value("ph", "");
    if (ph == "M") read_metadata(e, names);
    if (ph == "X") out.push_back(read_complete(e));
  }
  if (out.empty()) throw std::runtime_error("no complete (\"ph\": \"X\") events");
  for (TraceEvent& t : out) {
    const auto p = names.process.find(t.pid);
    t.process = p != names.process.end() ? p->second : "pid " + std::to_string(t.pid);
    const auto th = names.thread.find({t.pid, t.tid});
    t.thread = th != names.thread.end() ? th->second : "tid " + std::to_string(t.tid);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Tableau-10 colours: the seven stages first, then anything else by hash.
const char* stage_colour(const std::string& name) {
  static const char* palette[] = {"#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#76b7b2",
                                  "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};
  Stage s;
  if (parse_stage(name, s)) return palette[int(s)];
  return palette[kStageCount + std::hash<std::string>{}(name) % (10 - kStageCount)];
}

std::string fmt(const char* format, auto... args) {
  const int n = std::snprintf(nullptr, 0, format, args...);
  std::string out(size_t(std::max(n, 0)) + 1, '\0');
  std::snprintf(out.data(), out.size(), format, args...);
  out.pop_back();
  return out;
}

// 1, 2 or 5 times a power of ten, so that about `target` ticks span `range`.
double tick_step(double range, int target) {
  const double raw = range / target;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

struct Row {
  int pid;
  std::string process, label;
};

// Rows in order: by process, then by lane (tid) or by stage (in pipeline order).
std::vector<Row> make_rows(std::vector<TraceEvent>& events, GanttOptions::Rows by, std::vector<size_t>& row_of) {
  auto stage_rank = [](const std::string& name) {
    Stage s;
    return parse_stage(name, s) ? int(s) : kStageCount;
  };
  using Key = std::tuple<int, int, std::string>;  // pid, tid or stage rank, label
  std::map<Key, size_t> index;
  for (const TraceEvent& e : events) {
    const Key k = by == GanttOptions::Rows::lane ? Key{e.pid, e.tid, e.thread} : Key{e.pid, stage_rank(e.name), e.name};
    index.emplace(k, 0);
  }
  if (index.size() > kMaxRows)
    throw UsageError("the trace has " + std::to_string(index.size()) +
                     " rows (lanes or stage names); a chart shows at most " + std::to_string(kMaxRows));
  std::vector<Row> rows;
  for (auto& [key, i] : index) {
    i = rows.size();
    rows.push_back({std::get<0>(key), "", std::get<2>(key)});
  }
  row_of.clear();
  for (const TraceEvent& e : events) {
    const Key k = by == GanttOptions::Rows::lane ? Key{e.pid, e.tid, e.thread} : Key{e.pid, stage_rank(e.name), e.name};
    const size_t r = index[k];
    rows[r].process = e.process;
    row_of.push_back(r);
  }
  return rows;
}

// Shifts each process's events so that its first one starts at 0.
void align_processes(std::vector<TraceEvent>& events) {
  std::map<int, double> first;
  for (const TraceEvent& e : events) {
    auto [it, fresh] = first.emplace(e.pid, e.ts_us);
    if (!fresh) it->second = std::min(it->second, e.ts_us);
  }
  for (TraceEvent& e : events) e.ts_us -= first[e.pid];
}

}  // namespace

std::vector<TraceEvent> read_chrome_trace(const std::filesystem::path& path) {
  const std::string text = read_text_file(path, uint64_t(1) << 30);
  try {
    return parse_trace(json::parse(text));
  } catch (const json::exception& e) {
    input_error(path.string(), std::string("not valid JSON: ") + e.what());
  } catch (const std::runtime_error& e) {
    input_error(path.string(), std::string("not a Chrome trace: ") + e.what());
  }
}

std::string gantt_svg(const std::vector<TraceEvent>& input, const GanttOptions& options) {
  std::vector<TraceEvent> events = input;
  if (options.align_processes) align_processes(events);
  std::vector<size_t> row_of;
  const std::vector<Row> rows = make_rows(events, options.rows, row_of);

  double t0 = INFINITY, t1 = -INFINITY;
  for (const TraceEvent& e : events) t0 = std::min(t0, e.ts_us), t1 = std::max(t1, e.ts_us + e.dur_us);
  const double span_ms = std::max((t1 - t0) * 1e-3, 1e-3);

  // Layout: a label column, one band per row, a blank header line per process, axis and legend.
  const int label_w = 170, right = 20, top = 40, row_h = 22, header_h = 18;
  const int plot_w = std::max(200, options.width - label_w - right);
  std::vector<int> row_y(rows.size());
  int y = top;
  for (size_t r = 0; r < rows.size(); ++r) {
    if (r == 0 || rows[r].pid != rows[r - 1].pid) y += header_h;
    row_y[r] = y;
    y += row_h;
  }
  const int axis_y = y + 4, legend_y = axis_y + 40, height = legend_y + 30;
  auto x_of = [&](double ts_us) { return label_w + (ts_us - t0) * 1e-3 / span_ms * plot_w; };

  std::string svg =
      fmt("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
          "font-family=\"sans-serif\" font-size=\"11\">\n",
          options.width, height, options.width, height);
  svg += fmt("<rect width=\"%d\" height=\"%d\" fill=\"white\"/>\n", options.width, height);
  svg += fmt("<text x=\"%d\" y=\"22\" font-size=\"14\" font-weight=\"bold\">%s</text>\n", label_w,
             xml_escape(options.title).c_str());

  // Grid lines and tick labels (milliseconds since the first event).
  const double step_ms = tick_step(span_ms, 10);
  for (int k = 0; k <= 1000 && k * step_ms <= span_ms + 1e-9; ++k) {  // counted: a float sum could stall
    const double ms = k * step_ms;
    const double x = label_w + ms / span_ms * plot_w;
    svg += fmt("<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"#ddd\"/>\n", x, top, x, axis_y);
    svg += fmt("<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"black\"/>\n", x, axis_y, x, axis_y + 5);
    svg += fmt("<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%g</text>\n", x, axis_y + 17, ms);
  }
  svg += fmt("<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", label_w, axis_y, label_w + plot_w,
             axis_y);
  svg += fmt("<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">time [ms]</text>\n", label_w + plot_w / 2, axis_y + 32);

  // Row labels, with the process name above its first row.
  for (size_t r = 0; r < rows.size(); ++r) {
    if (r == 0 || rows[r].pid != rows[r - 1].pid)
      svg += fmt("<text x=\"4\" y=\"%d\" font-weight=\"bold\">%s</text>\n", row_y[r] - 5,
                 xml_escape(rows[r].process).c_str());
    svg += fmt("<text x=\"14\" y=\"%d\">%s</text>\n", row_y[r] + row_h / 2 + 4, xml_escape(rows[r].label).c_str());
  }

  // Bars: at least one pixel wide so that short stages stay visible; step label when it fits.
  for (size_t i = 0; i < events.size(); ++i) {
    const TraceEvent& e = events[i];
    const double x = x_of(e.ts_us), w = std::max(1.0, x_of(e.ts_us + e.dur_us) - x);
    const int by = row_y[row_of[i]] + 2;
    svg +=
        fmt("<rect x=\"%.2f\" y=\"%d\" width=\"%.2f\" height=\"%d\" fill=\"%s\" stroke=\"white\" stroke-width=\"0.5\">"
            "<title>%s step %d: %.3f ms</title></rect>\n",
            x, by, w, row_h - 4, stage_colour(e.name), xml_escape(e.name).c_str(), e.step, e.dur_us * 1e-3);
    const std::string label = e.step >= 0 ? std::to_string(e.step) : "";
    if (!label.empty() && w > 7.0 * double(label.size()) + 4)
      svg += fmt("<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\" fill=\"white\" font-size=\"10\">%s</text>\n",
                 x + w / 2, by + row_h / 2 + 2, label.c_str());
  }

  // Legend: the stages that occur, in pipeline order.
  const std::set<std::string> distinct = [&] {
    std::set<std::string> d;
    for (const TraceEvent& e : events) d.insert(e.name);
    return d;
  }();
  std::vector<std::string> names(distinct.begin(), distinct.end());
  std::stable_sort(names.begin(), names.end(), [](const std::string& a, const std::string& b) {
    Stage sa, sb;
    return (parse_stage(a, sa) ? int(sa) : kStageCount) < (parse_stage(b, sb) ? int(sb) : kStageCount);
  });
  int lx = label_w;
  for (const std::string& n : names) {
    svg += fmt("<rect x=\"%d\" y=\"%d\" width=\"12\" height=\"12\" fill=\"%s\"/>\n", lx, legend_y, stage_colour(n));
    svg += fmt("<text x=\"%d\" y=\"%d\">%s</text>\n", lx + 16, legend_y + 10, xml_escape(n).c_str());
    lx += 30 + 7 * int(n.size());
  }
  svg += fmt("<text x=\"%d\" y=\"%d\" fill=\"#555\">bar label = time step</text>\n", lx + 10, legend_y + 10);
  svg += "</svg>\n";
  return svg;
}

}  // namespace vs::stream
