// timeline: draw a Chrome-trace timeline (from play or bench stream) as an SVG Gantt chart.
#include <cstdio>

#include "commands.h"
#include "volstream/core/error.h"
#include "volstream/io/atomic_file.h"
#include "volstream/io/binary_file.h"
#include "volstream/stream/gantt.h"

namespace vs::cli {

void add_timeline_command(CLI::App& app) {
  struct Args {
    std::string input, output, rows = "lane", title;
    int width = 1200;
    bool absolute = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("timeline", "Draw a timeline JSON (play/bench --timeline) as an SVG Gantt chart");
  cmd->add_option("trace", a->input, "Chrome-trace JSON file")->required();
  cmd->add_option("-o,--output", a->output, "SVG file")->required();
  cmd->add_option("--rows", a->rows, "one row per lane (thread) or per stage")
      ->check(CLI::IsMember({"lane", "stage"}))
      ->capture_default_str();
  cmd->add_option("--width", a->width, "width in pixels")->check(CLI::Range(400, 20000))->capture_default_str();
  cmd->add_option("--title", a->title, "chart title (default: the file name)");
  cmd->add_flag("--absolute", a->absolute, "one time axis for all runs instead of starting each run at 0");
  cmd->callback([a] {
    check_output_directory(a->output);
    const auto events = stream::read_chrome_trace(a->input);
    stream::GanttOptions options;
    options.rows = a->rows == "stage" ? stream::GanttOptions::Rows::stage : stream::GanttOptions::Rows::lane;
    options.width = a->width;
    options.title = a->title.empty() ? std::filesystem::path(a->input).filename().string() : a->title;
    options.align_processes = !a->absolute;
    const std::string svg = stream::gantt_svg(events, options);
    write_file(a->output, svg.data(), svg.size());  // atomic, every write and the close checked
    std::printf("wrote %s: %zu events\n", a->output.c_str(), events.size());
  });
}

}  // namespace vs::cli
