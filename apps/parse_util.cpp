#include "parse_util.h"

#include <cmath>
#include <sstream>

#include "volstream/core/error.h"

namespace vs::cli {

std::vector<double> parse_numbers(const std::string& text, const std::string& what, char sep) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, sep)) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(v))
      throw UsageError(what + ": '" + item + "' is not a number");
    out.push_back(v);
  }
  return out;
}

double parse_number(const std::string& text, const std::string& what) {
  const auto v = parse_numbers(text, what);
  if (v.size() != 1) throw UsageError(what + ": '" + text + "' is not a number");
  return v[0];
}

vec3d parse_vec3(const std::string& text, const std::string& what) {
  const auto v = parse_numbers(text, what);
  if (v.size() != 3) throw UsageError(what + " expects X,Y,Z");
  return {v[0], v[1], v[2]};
}

namespace {

// A whole decimal integer, or UsageError naming `what`.
long long parse_int(const std::string& text, const std::string& what) {
  size_t used = 0;
  long long v = 0;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw UsageError(what + ": '" + text + "' is not an integer");
  return v;
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, sep)) parts.push_back(item);
  if (!text.empty() && text.back() == sep) parts.emplace_back();
  return parts;
}

int checked_step(long long s, int step_count) {
  if (s < 0 || s >= step_count)
    throw UsageError("--steps: step " + std::to_string(s) + " out of range 0.." + std::to_string(step_count - 1));
  return int(s);
}

}  // namespace

std::vector<int> parse_steps(const std::string& text, int step_count) {
  std::vector<int> steps;
  if (text.empty()) {
    for (int s = 0; s < step_count; ++s) steps.push_back(s);
    return steps;
  }
  if (text.find(':') == std::string::npos) {
    for (const std::string& item : split(text, ','))
      steps.push_back(checked_step(parse_int(item, "--steps"), step_count));
    return steps;
  }
  const auto parts = split(text, ':');
  if (parts.size() > 3) throw UsageError("--steps expects A:B[:S] or a list S1,S2,...");
  const long long a = parse_int(parts[0], "--steps"), b = parse_int(parts[1], "--steps");
  const long long stride = parts.size() == 3 ? parse_int(parts[2], "--steps") : 1;
  if (stride < 1) throw UsageError("--steps: the stride must be at least 1");
  if (a >= b) throw UsageError("--steps " + text + ": empty range (A:B is half-open, A < B)");
  checked_step(a, step_count);
  checked_step(b - 1, step_count);
  for (long long s = a; s < b; s += stride) steps.push_back(int(s));
  return steps;
}

}  // namespace vs::cli
