// probe: values of a field at world-space points, through the ABRs (or the brute-force sum).
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "volstream/core/error.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/dataset.h"

namespace vs::cli {
namespace {

// At most this much text of points (some 8 million points): /dev/zero or a huge file given
// by mistake is refused instead of read until memory runs out.
constexpr uint64_t kMaxPointsBytes = uint64_t(256) << 20;

// One point per line, "x y z" (nan and inf as strtod reads them: such a point prints nan, so
// the output keeps one line per point); blank lines are skipped.
std::vector<vec3d> parse_points(const std::string& text, const std::string& name) {
  std::vector<vec3d> points;
  uint64_t n = 0;
  for (size_t begin = 0; begin < text.size();) {
    const size_t end = std::min(text.find('\n', begin), text.size());
    const std::string line = text.substr(begin, end - begin);
    begin = end + 1;
    ++n;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const char* p = line.c_str();
    char* next = nullptr;
    vec3d v;
    for (int a = 0; a < 3; ++a, p = next) {
      v[a] = std::strtod(p, &next);
      if (next == p) input_error(name, "line " + std::to_string(n) + ": expected three numbers 'x y z'");
    }
    if (std::string(next).find_first_not_of(" \t\r") != std::string::npos)
      input_error(name, "line " + std::to_string(n) + ": expected three numbers 'x y z'");
    points.push_back(v);
  }
  return points;
}

std::string read_stdin_capped() {
  std::string text;
  char buf[1 << 16];
  while (std::cin.read(buf, sizeof buf) || std::cin.gcount() > 0) {
    text.append(buf, size_t(std::cin.gcount()));
    if (text.size() > kMaxPointsBytes) input_error("<stdin>", "more than 256 MiB of points");
  }
  return text;
}

}  // namespace

void add_probe_command(CLI::App& app) {
  struct Args {
    std::string dir, field, points;
    int step = 0;
    std::string device = "cpu";
    std::string encoding = "stored";
    bool brute = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd =
      app.add_subcommand("probe", "Print the field's value at points 'x y z' (world coordinates), one per line");
  cmd->add_option("dataset", a->dir, "dataset directory")->required();
  cmd->add_option("--field", a->field, "field name (default: the first)");
  cmd->add_option("--step", a->step, "time step")->capture_default_str();
  cmd->add_option("--points", a->points, "file of points (default: stdin)");
  cmd->add_flag("--brute-force", a->brute,
                "sum over all cells instead of the ABRs, or test every mesh element (either encoding): the reference");
  cmd->add_option("--device", a->device, "cpu | cuda | auto: where the ABR probes run")->capture_default_str();
  cmd->add_option("--encoding", a->encoding,
                  "meshes: stored (the dataset's) | reference | compact (paper 002's encoding; built at load from a "
                  "reference dataset)")
      ->check(CLI::IsMember({"stored", "reference", "compact"}))
      ->capture_default_str();
  cmd->callback([a] {
    const Dataset ds(a->dir);
    const auto& m = ds.manifest();
    const int field = a->field.empty() ? 0 : m.field_index(a->field);
    if (field < 0) throw UsageError("no field '" + a->field + "' in " + a->dir);
    if (a->step < 0 || a->step >= m.step_count())
      throw UsageError("step " + std::to_string(a->step) + " out of range 0.." + std::to_string(m.step_count() - 1));
    std::vector<vec3d> world;
    if (a->points.empty())
      world = parse_points(read_stdin_capped(), "<stdin>");
    else
      world = parse_points(read_text_file(a->points, kMaxPointsBytes), a->points);
    std::vector<double> out(world.size());
    if (a->brute) {
      out = probe_brute_force(ds, field, a->step, world);
    } else {
      FrameRenderer renderer(ds, resolve_device(a->device, ds, parse_mesh_encoding(a->encoding)));
      const std::vector<float> v = renderer.probe(field, a->step, world, parse_mesh_encoding(a->encoding));
      std::copy(v.begin(), v.end(), out.begin());
    }
    std::string text;
    char buf[32];
    for (double v : out) {
      if (std::isnan(v))
        text += "nan\n";
      else
        text += std::string(buf, size_t(std::snprintf(buf, sizeof(buf), "%.9g\n", v)));
    }
    std::fputs(text.c_str(), stdout);
  });
}

}  // namespace vs::cli
