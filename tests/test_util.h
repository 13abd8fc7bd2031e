// Helpers shared by the tests.
#pragma once
#include <filesystem>
#include <string>

namespace vs::test {
// A fresh empty directory under the build tree's temp area, unique per test.
std::filesystem::path scratch_dir(const std::string& name);
}  // namespace vs::test
