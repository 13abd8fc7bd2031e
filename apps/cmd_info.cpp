#include <cstdio>

#include "commands.h"
#include "volstream/cuda/scene_bytes.h"
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
    auto summary = dataset_summary(ds);
    // What a GPU render of one field at 512x512 allocates on the device (DeviceScene).
    uint64_t total = 0;
    for (const auto& [structure, bytes] : cuda::device_scene_bytes(ds.topology(), 1, 512, 512)) {
      summary["device_bytes"][structure] = bytes;
      total += bytes;
    }
    summary["device_bytes"]["total (one field, 512x512)"] = total;
    const std::string text = *as_json ? summary.dump(2) + "\n" : format_summary(summary);
    std::fputs(text.c_str(), stdout);
  });
}

}  // namespace vs::cli
