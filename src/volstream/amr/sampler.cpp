#include "volstream/amr/sampler.h"

#include <algorithm>

#include "volstream/backend/parallel.h"

namespace vs {

double sample_brute_force(const Cell* cells, const float* values, uint64_t n, const vec3d& p) {
  double weight = 0, weighted = 0;
  for (uint64_t i = 0; i < n; ++i) {
    const Cell& c = cells[i];
    const double w = double(level_width(c.level));
    double wgt = 1;
    for (int a = 0; a < 3 && wgt > 0; ++a) {
      const double centre = c.lower[a] + 0.5 * w;
      wgt *= std::max(0.0, 1.0 - std::fabs(p[a] - centre) / w);
    }
    if (wgt > 0) {
      weight += wgt;
      weighted += wgt * values[i];
    }
  }
  return weight > 0 ? weighted / weight : NAN;
}

std::vector<SampleBrick> make_sample_bricks(const AmrTopology& topology) {
  std::vector<SampleBrick> out;
  out.reserve(topology.bricks.size());
  for (const Brick& b : topology.bricks)
    out.push_back({vec3f(b.lower), 1.f / float(b.width()), b.dims, 0u, b.value_offset});
  return out;
}

}  // namespace vs
