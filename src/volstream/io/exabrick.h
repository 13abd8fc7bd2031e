// ExaBrick cell and scalar files. Cells: N records of four little-endian int32 {x, y, z, level},
// the lower corner in finest cell widths, level 0 finest, width 2^level. Scalars: N float32 in the
// same order, one file per field (or per step with `as_time_series`).
#pragma once
#include <filesystem>
#include <memory>
#include <vector>

#include "volstream/amr/source.h"

namespace vs {

struct ExaBrickInput {
  std::filesystem::path cells;
  std::vector<std::filesystem::path> scalars;  // fields named by file stem
  bool as_time_series = false;                 // scalars are steps of one field instead
  std::string series_field_name = "scalar";
};

std::unique_ptr<AmrSource> open_exabrick(const ExaBrickInput& input);
void write_exabrick_cells(const std::filesystem::path& path, const std::vector<Cell>& cells);
void write_exabrick_scalars(const std::filesystem::path& path, const std::vector<float>& values);

}  // namespace vs
