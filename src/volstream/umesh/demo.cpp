#include "volstream/umesh/demo.h"

#include <algorithm>
#include <cmath>

#include "volstream/core/error.h"

namespace vs {
namespace {

// Grid of (n+1)^3 points; point (i, j, k) has index ((k * (n+1)) + j) * (n+1) + i.
struct Lattice {
  int n;
  uint64_t id(int i, int j, int k) const {
    return (uint64_t(k) * uint64_t(n + 1) + uint64_t(j)) * uint64_t(n + 1) + uint64_t(i);
  }
};

double hash_unit(uint64_t x) {  // deterministic jitter in [-0.5, 0.5)
  x ^= x >> 33;
  x *= 0xff51afd7ed558ccdULL;
  x ^= x >> 33;
  x *= 0xc4ceb9fe1a85ec53ULL;
  x ^= x >> 33;
  return double(x >> 11) * (1.0 / 9007199254740992.0) - 0.5;
}

// Jittered interior points of the unit box (boundary points stay on the faces).
vec3d tets_point(const Lattice& l, int i, int j, int k) {
  const double h = 1.0 / l.n;
  vec3d p(i * h, j * h, k * h);
  const int c[3] = {i, j, k};
  for (int a = 0; a < 3; ++a)
    if (c[a] > 0 && c[a] < l.n) p[a] += 0.25 * h * hash_unit(l.id(i, j, k) * 3 + uint64_t(a));
  return p;
}

// A twist about the box's vertical axis growing with height, and a warp of the layers: every
// face of the grid's hexes is a non-planar ruled surface.
vec3d mixed_point(const Lattice& l, int i, int j, int k) {
  const double h = 1.0 / l.n;
  const double x = i * h - 0.5, y = j * h - 0.5, z = k * h;
  const double angle = 0.6 * z;
  const double c = std::cos(angle), s = std::sin(angle);
  const double warp = 0.3 * h * std::sin(6.0 * x) * std::sin(5.0 * y);
  return {0.5 + c * x - s * y, 0.5 + s * x + c * y, z + warp};
}

void add_cell(MeshData& m, uint8_t type, std::initializer_list<uint64_t> ids) {
  m.cell_types.push_back(type);
  m.connectivity.insert(m.connectivity.end(), ids);
  m.cell_offsets.push_back(m.connectivity.size());
}

// Hex corners in VTK order: bottom face counter-clockwise seen from above, then the top face.
void hex_corners(const Lattice& l, int i, int j, int k, uint64_t v[8]) {
  v[0] = l.id(i, j, k), v[1] = l.id(i + 1, j, k), v[2] = l.id(i + 1, j + 1, k), v[3] = l.id(i, j + 1, k);
  v[4] = l.id(i, j, k + 1), v[5] = l.id(i + 1, j, k + 1), v[6] = l.id(i + 1, j + 1, k + 1),
  v[7] = l.id(i, j + 1, k + 1);
}

// Six tets around the diagonal 0-6 (Kuhn's split: neighbouring hexes cut shared faces alike).
void add_kuhn_tets(MeshData& m, const uint64_t v[8]) {
  const int paths[6][2] = {{1, 2}, {2, 3}, {3, 7}, {7, 4}, {4, 5}, {5, 1}};
  for (const auto& p : paths) add_cell(m, 10, {v[0], v[p[0]], v[p[1]], v[6]});
}

// Every element in VTK's orientation for its type (make_umesh refuses inverted ones).
void add_hex_as_type(MeshData& m, const uint64_t v[8], int column_type, uint64_t centre) {
  switch (column_type) {
    case 0:
      add_cell(m, 12, {v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]});
      break;
    case 1:  // two wedges split by the vertical diagonal plane 0-2-6-4; VTK's wedge has the
             // normal of its first triangle pointing away from the second
      add_cell(m, 13, {v[0], v[2], v[1], v[4], v[6], v[5]});
      add_cell(m, 13, {v[0], v[3], v[2], v[4], v[7], v[6]});
      break;
    default: {  // six pyramids: each face of the hex as a base (normal inwards), apex at the centre
      const int faces[6][4] = {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1}, {1, 5, 6, 2}, {2, 6, 7, 3}, {3, 7, 4, 0}};
      for (const auto& f : faces) add_cell(m, 14, {v[f[0]], v[f[1]], v[f[2]], v[f[3]], centre});
    }
  }
}

int grid_size(const MeshDemoOptions& o) {
  const double per_hex = o.name == "mixed" ? 8.0 / 3.0 : 6.0;  // mean elements per grid cell
  return std::max(1, int(std::lround(std::cbrt(double(o.target_elements) / per_hex))));
}

bool in_hole(const vec3d& c) {
  const vec3d d = c - vec3d(0.5, 0.5, 0.5);
  const bool cavity = dot(d, d) < 0.25 * 0.25;
  const bool notch = c.x > 0.75 && c.z > 0.35 && c.z < 0.65;
  return cavity || notch;
}

void build_tets(MeshData& m, int n, bool holes) {
  const Lattice l{n};
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) m.points.push_back(tets_point(l, i, j, k));
  const double h = 1.0 / n;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        if (holes && in_hole(vec3d((i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h))) continue;
        uint64_t v[8];
        hex_corners(l, i, j, k, v);
        add_kuhn_tets(m, v);
      }
}

// The second part of "holes": a box of a third of the size, beside the first.
void add_island(MeshData& m, int n) {
  const int s = std::max(1, n / 3);
  const Lattice l{s};
  const uint64_t base = m.points.size();
  for (int k = 0; k <= s; ++k)
    for (int j = 0; j <= s; ++j)
      for (int i = 0; i <= s; ++i)
        m.points.push_back(vec3d(1.2 + i / (3.0 * s), 0.3 + j / (3.0 * s), 0.3 + k / (3.0 * s)));
  for (int k = 0; k < s; ++k)
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i) {
        uint64_t v[8];
        hex_corners(l, i, j, k, v);
        for (uint64_t& x : v) x += base;
        add_kuhn_tets(m, v);
      }
}

void build_mixed(MeshData& m, int n) {
  const Lattice l{n};
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) m.points.push_back(mixed_point(l, i, j, k));
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        uint64_t v[8];
        hex_corners(l, i, j, k, v);
        const int column_type = (i + 2 * j) % 3;
        uint64_t centre = 0;
        if (column_type == 2) {
          vec3d c(0.0);
          for (uint64_t x : v) c = c + m.points[x] * 0.125;
          centre = m.points.size();
          m.points.push_back(c);
        }
        add_hex_as_type(m, v, column_type, centre);
      }
}

double density(const vec3d& p, int step) {
  double f = 0.02;
  const double drift = 0.05 * step;
  const vec3d blobs[3] = {{0.3 + drift, 0.35, 0.4}, {0.7, 0.6 - drift, 0.55}, {0.45, 0.7, 0.3 + drift}};
  const double widths[3] = {0.12, 0.09, 0.15};
  for (int b = 0; b < 3; ++b) {
    const vec3d d = p - blobs[b];
    f += std::exp(-dot(d, d) / (2 * widths[b] * widths[b]));
  }
  return f;
}

}  // namespace

std::vector<std::string> mesh_demo_names() { return {"tets", "mixed", "holes"}; }
bool is_mesh_demo(const std::string& name) {
  const auto names = mesh_demo_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

void check_mesh_demo(const MeshDemoOptions& o) {
  if (!is_mesh_demo(o.name)) throw UsageError("unknown mesh demo '" + o.name + "' (tets, mixed, holes)");
  if (o.target_elements < 6 || o.target_elements > 500'000'000)
    throw UsageError("mesh demo elements must be in [6, 5e8]");
  if (o.steps < 1) throw UsageError("steps must be at least 1");
}

MeshData make_mesh_demo(const MeshDemoOptions& o, int step) {
  check_mesh_demo(o);
  MeshData m;
  m.cell_offsets.push_back(0);
  const int n = grid_size(o);
  if (o.name == "mixed") {
    build_mixed(m, n);
  } else {
    build_tets(m, n, o.name == "holes");
    if (o.name == "holes") add_island(m, n);
  }
  MeshArray dens{"density", 1, std::vector<double>(m.points.size())};
  MeshArray linear{"linear", 1, std::vector<double>(m.points.size())};
  for (size_t i = 0; i < m.points.size(); ++i) {
    dens.values[i] = density(m.points[i], step);
    linear.values[i] = m.points[i].x + 2 * m.points[i].y + 3 * m.points[i].z;
  }
  m.point_data = {std::move(dens), std::move(linear)};
  return m;
}

}  // namespace vs
