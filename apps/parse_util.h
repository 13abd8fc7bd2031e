// Parsing of comma-separated command-line values shared by the subcommands.
#pragma once
#include <string>
#include <vector>

#include "volstream/core/math.h"

namespace vs::cli {
// Finite numbers separated by `sep`, or UsageError naming `what`.
std::vector<double> parse_numbers(const std::string& text, const std::string& what, char sep = ',');
// Exactly three numbers X,Y,Z.
vec3d parse_vec3(const std::string& text, const std::string& what);
}  // namespace vs::cli
