// Parsing of comma-separated command-line values shared by the subcommands.
#pragma once
#include <string>
#include <vector>

#include "volstream/core/math.h"

namespace vs::cli {
// Finite numbers separated by `sep`, or UsageError naming `what`.
std::vector<double> parse_numbers(const std::string& text, const std::string& what, char sep = ',');
// Exactly one finite number.
double parse_number(const std::string& text, const std::string& what);
// Exactly three numbers X,Y,Z.
vec3d parse_vec3(const std::string& text, const std::string& what);
// --steps: "A:B" (half-open), "A:B:S" (stride S) or "17,3,250" (listed, in that order); empty = all.
// UsageError for malformed text, an empty range or a step outside [0, step_count).
std::vector<int> parse_steps(const std::string& text, int step_count);
}  // namespace vs::cli
