// A small mesh with one cell of each supported type (tet, pyramid, wedge, hex, in the order UGRID
// stores them), all positively oriented in VTK's conventions, with a point scalar, a point
// 3-vector, a 2-component point array and a cell scalar; and comparisons for round trips.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "volstream/umesh/mesh_data.h"

namespace vs::test {

inline MeshData mixed_mesh() {
  MeshData m;
  // Points 0-7: a unit cube (VTK hex order); 8 apex above its top; 9, 10 extend it in x for the
  // wedge; 11 below the bottom for the tet. Coordinates not exact in float32 on purpose.
  m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},       {0, 1, 0},   {0, 0, 1},   {1, 0, 1},
              {1, 1, 1}, {0, 1, 1}, {0.5, 0.5, 2.1}, {2.3, 0, 0}, {2.3, 0, 1}, {0.1, 0.2, -0.7}};
  auto add = [&m](CellType t, std::initializer_list<uint64_t> v) {
    m.cell_types.push_back(uint8_t(t));
    m.connectivity.insert(m.connectivity.end(), v);
    m.cell_offsets.push_back(m.connectivity.size());
  };
  m.cell_offsets = {0};
  add(CellType::tet, {0, 3, 1, 11});
  add(CellType::pyramid, {4, 5, 6, 7, 8});
  add(CellType::wedge, {1, 2, 9, 5, 6, 10});
  add(CellType::hex, {0, 1, 2, 3, 4, 5, 6, 7});
  MeshArray temperature{"temperature", 1, {}}, velocity{"velocity", 3, {}}, uv{"uv", 2, {}};
  for (size_t i = 0; i < m.points.size(); ++i) {
    temperature.values.push_back(300.0 + i / 3.0);
    velocity.values.insert(velocity.values.end(), {0.1 * i, -1.0 / (i + 1), 1e-7 * i});
    uv.values.insert(uv.values.end(), {double(i), 0.25 * i});
  }
  m.point_data = {temperature, velocity, uv};
  m.cell_data = {MeshArray{"pressure", 1, {1.5, -2.0 / 3.0, 1e5, 7.0}}};
  return m;
}

inline double to_f32(double v) { return double(float(v)); }

// Points compared after float32 rounding when `points_f32`; topology exactly.
inline void expect_same_geometry(const MeshData& a, const MeshData& b, bool points_f32) {
  ASSERT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(points_f32 ? to_f32(a.points[i][c]) : a.points[i][c], b.points[i][c]) << "point " << i << "." << c;
  EXPECT_EQ(a.cell_types, b.cell_types);
  EXPECT_EQ(a.cell_offsets, b.cell_offsets);
  EXPECT_EQ(a.connectivity, b.connectivity);
}

inline void expect_same_arrays(const std::vector<MeshArray>& a, const std::vector<MeshArray>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].components, b[i].components);
    EXPECT_EQ(a[i].values, b[i].values) << a[i].name;
  }
}

// Six times the signed volume of tet (a, b, c, d): positive when (b-a)x(c-a) points towards d.
inline double tet_volume6(const vec3d& a, const vec3d& b, const vec3d& c, const vec3d& d) {
  const vec3d u = b - a, v = c - a, w = d - a;
  return (u.y * v.z - u.z * v.y) * w.x + (u.z * v.x - u.x * v.z) * w.y + (u.x * v.y - u.y * v.x) * w.z;
}

}  // namespace vs::test
