// The pyramid's closed-form inverse (pyramid_closed_form.diff applied to the sources) against
// the forward map and against Newton's iteration from the centre, on random warped pyramids.
// Not built by the project: g++ -std=c++20 -O2 -Isrc -I<build dir> pyramid_check.cpp
#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

#include "volstream/umesh/shape.h"

using namespace vs;

namespace {

float largest_difference(const vec3f& a, const vec3f& b) {
  return std::max({std::fabs(a.x - b.x), std::fabs(a.y - b.y), std::fabs(a.z - b.z)});
}

}  // namespace

int main() {
  std::mt19937 rng(4242);
  std::uniform_real_distribution<float> around(-0.3f, 1.3f), height(-0.3f, 0.9f), distort(-0.12f, 0.12f),
      lift(-0.25f, 0.25f);
  float worst_map = 0.f, worst_newton = 0.f;
  int declined = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    std::vector<vec3f> x = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 1}};
    for (vec3f& corner : x) corner = corner + vec3f(distort(rng), distort(rng), distort(rng));
    x[2].z += lift(rng), x[3].z += lift(rng);  // a non-planar base
    const vec3f made{around(rng), around(rng), height(rng)};
    float w[8];
    vec3f d[8];
    shape::weights(5, made.x, made.y, made.z, w, d);
    vec3f p(0.f);
    for (int i = 0; i < 5; ++i) p = p + x[size_t(i)] * w[i];
    const shape::IsoSolve solve = shape::iso_solve(5, x.data());
    vec3f closed;
    if (!shape::pyramid_params(solve.map, p - solve.origin, closed)) {
      ++declined;
      continue;
    }
    if (shape::params_outside(5, made.x, made.y, made.z) < -0.01f)
      worst_map = std::max(worst_map, largest_difference(closed, made));
    shape::IsoSolve newton = solve;
    if (shape::newton_params(5, newton, p - solve.origin, nullptr, false, 1) &&
        shape::params_outside(5, newton.params.x, newton.params.y, newton.params.z) < 0.f)
      worst_newton = std::max(worst_newton, largest_difference(newton.params, closed));
  }
  std::printf("worst vs map %g vs newton %g fails %d\n", worst_map, worst_newton, declined);
}
