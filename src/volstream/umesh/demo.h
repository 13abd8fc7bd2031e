// Built-in procedural unstructured meshes, for trying the tool, tests and benchmarks:
//   tets    a unit box of n^3 jittered hexes each cut into 6 tetrahedra (conforming), with a
//           field "density" of a few Gaussian blobs drifting from step to step
//   mixed   a twisted, warped n^3 grid (hex faces are non-planar ruled surfaces) whose columns
//           are hexahedra, pairs of wedges or six pyramids around the hex's centre (conforming)
//   holes   the tet box with a spherical cavity, a notch cut from one side, and a second,
//           disconnected smaller box beside it: rays leave and re-enter the mesh
// Every demo also has "linear" = x + 2y + 3z (reproduced exactly by every element type).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "volstream/umesh/mesh_data.h"

namespace vs {

struct MeshDemoOptions {
  std::string name;                   // "tets", "mixed" or "holes"
  uint64_t target_elements = 100000;  // within a few percent (before holes are cut)
  int steps = 1;
};

std::vector<std::string> mesh_demo_names();
bool is_mesh_demo(const std::string& name);
// UsageError for an unknown name, target_elements outside [6, 5e8] or steps < 1.
void check_mesh_demo(const MeshDemoOptions& options);
// Step `step` (point fields "density" and "linear"; the mesh is the same at every step).
MeshData make_mesh_demo(const MeshDemoOptions& options, int step);

}  // namespace vs
