#include <cstdio>

#include "commands.h"
#include "volstream/io/dataset_info.h"

namespace vs::cli {

void add_info_command(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  auto as_json = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("info", "Describe a dataset: domain, levels, fields, steps, bricks, ABRs, memory");
  cmd->add_option("dataset", *dir, "dataset directory")->required();
  cmd->add_flag("--json", *as_json, "machine-readable output");
  cmd->callback([dir, as_json] {
    const Dataset ds(*dir);
    const auto summary = dataset_summary(ds);
    const std::string text = *as_json ? summary.dump(2) + "\n" : format_summary(summary);
    std::fputs(text.c_str(), stdout);
  });
}

}  // namespace vs::cli
