// probe: values of a field at world-space points, through the ABRs (or the brute-force sum).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "volstream/amr/probe.h"
#include "volstream/core/error.h"
#include "volstream/backend/parallel.h"
#include "volstream/io/dataset.h"

namespace vs::cli {
namespace {

std::vector<vec3d> read_points(std::istream& in, const std::string& name) {
  std::vector<vec3d> points;
  std::string line;
  for (uint64_t n = 1; std::getline(in, line); ++n) {
    std::istringstream ls(line);
    vec3d p;
    if (!(ls >> p.x)) continue;  // blank line
    if (!(ls >> p.y >> p.z)) input_error(name, "line " + std::to_string(n) + ": expected three numbers 'x y z'");
    points.push_back(p);
  }
  return points;
}

}  // namespace

void add_probe_command(CLI::App& app) {
  struct Args {
    std::string dir, field, points;
    int step = 0;
    bool brute = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("probe", "Print the field's value at points 'x y z' (world coordinates), one per line");
  cmd->add_option("dataset", a->dir, "dataset directory")->required();
  cmd->add_option("--field", a->field, "field name (default: the first)");
  cmd->add_option("--step", a->step, "time step")->capture_default_str();
  cmd->add_option("--points", a->points, "file of points (default: stdin)");
  cmd->add_flag("--brute-force", a->brute, "sum over all cells instead of the ABRs (the reference)");
  cmd->callback([a] {
    const Dataset ds(a->dir);
    const auto& m = ds.manifest();
    const int field = a->field.empty() ? 0 : m.field_index(a->field);
    if (field < 0) throw UsageError("no field '" + a->field + "' in " + a->dir);
    if (a->step < 0 || a->step >= m.step_count())
      throw UsageError("step " + std::to_string(a->step) + " out of range 0.." + std::to_string(m.step_count() - 1));
    std::vector<vec3d> world;
    if (a->points.empty()) {
      world = read_points(std::cin, "<stdin>");
    } else {
      std::ifstream in(a->points);
      if (!in) input_error(a->points, "cannot open");
      world = read_points(in, a->points);
    }
    const std::vector<float> values = ds.load_values(field, a->step);
    std::vector<double> out(world.size());
    if (a->brute) {
      const std::vector<Cell> cells = ds.load_cells();
      parallel_for("probe_brute", int64_t(world.size()), [&](int64_t i) {
        out[size_t(i)] = sample_brute_force(cells.data(), values.data(), cells.size(), m.transform.to_grid(world[size_t(i)]));
      });
    } else {
      std::vector<vec3f> grid(world.size());
      for (size_t i = 0; i < world.size(); ++i) grid[i] = vec3f(m.transform.to_grid(world[i]));
      const Bvh bvh = build_abr_bvh(ds.topology());
      const auto v = probe_points(ds.topology(), bvh, values.data(), grid);
      for (size_t i = 0; i < v.size(); ++i) out[i] = v[i];
    }
    std::string text;
    char buf[32];
    for (double v : out) {
      if (std::isnan(v)) text += "nan\n";
      else text += std::string(buf, size_t(std::snprintf(buf, sizeof(buf), "%.9g\n", v)));
    }
    std::fputs(text.c_str(), stdout);
  });
}

}  // namespace vs::cli
