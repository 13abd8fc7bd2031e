#include "test_util.h"

#include <gtest/gtest.h>

namespace vs::test {
std::filesystem::path scratch_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string unique = name;
  if (info) unique = std::string(info->test_suite_name()) + "." + info->name() + "." + name;
  auto dir = std::filesystem::temp_directory_path() / "volstream_tests" / unique;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}
}  // namespace vs::test

#include <algorithm>
#include <cmath>
#include <random>

namespace vs::test {

namespace {
void refine_cell(const Cell& c, std::mt19937& rng, double refine, std::vector<Cell>& out) {
  std::uniform_real_distribution<double> u(0, 1);
  if (c.level == 0 || u(rng) >= refine) {
    out.push_back(c);
    return;
  }
  const int32_t half = level_width(c.level - 1);
  for (int k = 0; k < 8; ++k) {
    const vec3i off(k & 1 ? half : 0, k & 2 ? half : 0, k & 4 ? half : 0);
    refine_cell({c.lower + off, c.level - 1}, rng, refine, out);
  }
}
}  // namespace

std::vector<Cell> random_octree_cells(uint32_t seed, vec3i root_dims, int levels, double refine) {
  std::mt19937 rng(seed);
  std::vector<Cell> out;
  const int32_t w = level_width(levels - 1);
  for (int z = 0; z < root_dims.z; ++z)
    for (int y = 0; y < root_dims.y; ++y)
      for (int x = 0; x < root_dims.x; ++x) refine_cell({vec3i(x, y, z) * w, levels - 1}, rng, refine, out);
  std::shuffle(out.begin(), out.end(), rng);
  return out;
}

float test_value(const Cell& c, int variant) {
  const float w = float(level_width(c.level));
  const vec3f p = vec3f(c.lower) + vec3f(0.5f * w);
  return 1.5f + 0.4f * std::sin(0.21f * p.x + variant) * std::cos(0.13f * p.y) + 0.02f * float(c.level) +
         0.05f * std::sin(0.37f * p.z);
}

}  // namespace vs::test
