// The summary `volstream info` prints: sizes, levels, fields, bricks, ABRs and memory.
#pragma once
#include <nlohmann/json.hpp>

#include "volstream/io/dataset.h"

namespace vs {

struct BrickHistogramBin {
  uint64_t min_cells, max_cells;  // inclusive; bins are powers of two: 1, 2-3, 4-7, ...
  uint64_t bricks;
};

std::vector<BrickHistogramBin> cells_per_brick_histogram(const std::vector<Brick>& bricks);
nlohmann::json dataset_summary(const Dataset& ds);          // everything `info` shows
std::string format_summary(const nlohmann::json& summary);  // the human-readable text

}  // namespace vs
