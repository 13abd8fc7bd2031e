// Helpers shared by the tests.
#pragma once
#include <filesystem>
#include <string>

namespace vs::test {
// A fresh empty directory under the build tree's temp area, unique per test.
std::filesystem::path scratch_dir(const std::string& name);
}  // namespace vs::test

#include <cstdint>
#include <vector>

#include "volstream/amr/model.h"

namespace vs::test {
// Octree leaves: a root grid of cells at level `levels-1`, each refined into 8 children with
// probability `refine` (per level), deterministic for a seed. Cells come out shuffled.
std::vector<Cell> random_octree_cells(uint32_t seed, vec3i root_dims, int levels, double refine);
// A smooth test function of grid position (plus a per-cell jitter that makes level jumps visible).
float test_value(const Cell& c, int variant = 0);
}  // namespace vs::test
