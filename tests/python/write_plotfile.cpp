// Writes a small two-level, two-component AMReX plotfile (the C++ writer of io/plotfile.h) for
// the Python module's tests: `volstream_test_plotfile DIR`. Not installed.
#include <cstdio>

#include "volstream/io/plotfile.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  using namespace vs;
  PlotfileSpec spec;
  spec.components = {"density", "temperature"};
  spec.prob_lo = {0, 0, 0};
  spec.prob_hi = {2, 1, 1};
  spec.level0_domain = {vec3i(0, 0, 0), vec3i(15, 7, 7)};
  spec.ref_ratios = {2};
  spec.levels = {PlotfileLevel{{box3i{vec3i(0, 0, 0), vec3i(7, 7, 7)}, box3i{vec3i(8, 0, 0), vec3i(15, 7, 7)}}},
                 PlotfileLevel{{box3i{vec3i(6, 4, 4), vec3i(17, 11, 11)}}}};
  write_plotfile(argv[1], spec, [](int c, int l, int i, int j, int k) {
    const double s = l == 0 ? 1.0 : 0.5;  // cell centres in level-0 units
    const double x = (i + 0.5) * s, y = (j + 0.5) * s, z = (k + 0.5) * s;
    return c == 0 ? 1.0 + 0.1 * x + 0.05 * y * y + 0.02 * z : 100.0 + x * y + z;
  });
  return 0;
}
