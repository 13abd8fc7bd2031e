// Brick builder: merges same-level cells into dense boxes with a kd-tree split heuristic.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "volstream/amr/model.h"

namespace vs {

struct BrickBuildOptions {
  int max_brick_dim = 64;  // a dense box longer than this on an axis is split in the middle
};

struct BrickBuildResult {
  std::vector<Brick> bricks;          // sorted by value_offset
  std::vector<Cell> device_cells;     // cells in device order (brick by brick, x fastest)
  std::vector<uint32_t> input_index;  // input_index[device position] = position in the input
};

// Consumes `cells` (input order). Throws InputError(source_name, ...) for cells that are not
// aligned to their width, out of range, or duplicated.
BrickBuildResult build_bricks(std::vector<Cell>&& cells, const std::string& source_name,
                              const BrickBuildOptions& options = {});

}  // namespace vs
