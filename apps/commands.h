// Each subcommand registers itself on the CLI11 app; its callback runs the command.
#pragma once
#include <CLI/CLI.hpp>

namespace vs::cli {
void add_demo_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_probe_command(CLI::App& app);
}  // namespace vs::cli
