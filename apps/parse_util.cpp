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
    if (used == 0 || used != item.size() || !std::isfinite(v)) throw UsageError(what + ": '" + item + "' is not a number");
    out.push_back(v);
  }
  return out;
}

vec3d parse_vec3(const std::string& text, const std::string& what) {
  const auto v = parse_numbers(text, what);
  if (v.size() != 3) throw UsageError(what + " expects X,Y,Z");
  return {v[0], v[1], v[2]};
}

}  // namespace vs::cli
