// Built-in procedural AMR data sets, for trying the tool and for tests and benchmarks without
// downloading anything:
//   jet    an aircraft-like body in a uniform stream (40 x 20 x 20 m box): octree refinement over
//          6 levels clustered at the body's surface plus a refined wake; fields pressure (Pa, gauge),
//          velocity (m/s, magnitude) and vorticity (1/s, magnitude) of an analytic flow whose vortex
//          street and wingtip vortices are shed and advected downstream from step to step.
//   cosmo  a 32 Mpc box with collapsing clumps joined by filaments, refined like Enzo (where a cell's
//          mass exceeds a fixed threshold) over 6 levels; fields density (relative to the mean,
//          about 1e-3 .. 1e6) and temperature (K, about 1e2 .. 1e7).
// The cells are octree leaves covering the domain box exactly. Same options give bit-identical
// cells and values whatever the thread count. Values are computed on demand per (field, step).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "volstream/amr/source.h"

namespace vs {

struct DemoOptions {
  std::string name;                   // "jet" or "cosmo"
  uint64_t target_cells = 1'000'000;  // the result lands within a few percent of this
  int steps = 4;
};

std::vector<std::string> demo_names();  // {"jet", "cosmo"}

// Throws UsageError for an unknown name, target_cells outside [1e4, 2e9] or steps < 1.
std::unique_ptr<AmrSource> make_demo(const DemoOptions& options);

}  // namespace vs
