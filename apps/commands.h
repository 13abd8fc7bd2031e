// Each subcommand registers itself on the CLI11 app; its callback runs the command.
#pragma once
#include <CLI/CLI.hpp>

namespace vs::cli {
void add_demo_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_probe_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_play_command(CLI::App& app);
void add_timeline_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_view_command(CLI::App& app);         // only with civetweb and libjpeg-turbo (VOLSTREAM_HAVE_VIEWER)
void add_bench_integrators(CLI::App& bench);  // `bench integrators` (cmd_bench_integrators.cpp)
}  // namespace vs::cli

namespace vs::cli {
// --split-into-tets, of convert and demo (umesh/split_tets.h).
inline void add_split_into_tets_flag(CLI::App* cmd, bool& flag) {
  cmd->add_flag("--split-into-tets", flag,
                "meshes: store pyramids, wedges and hexahedra as 2, 3 and 6 tets over the same vertices (renders "
                "faster; interpolates linearly per tet instead of by the element's shape functions)");
}
}  // namespace vs::cli
