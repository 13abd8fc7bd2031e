#include "volstream/umesh/from_mesh_data.h"

#include <cmath>
#include <optional>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/umesh/shape.h"

namespace vs {
namespace {

// The parametric points of each type (shape.h) where Jacobians are taken: the corners and the
// centre (a hex whose top face is turned half around has positive corners and a singular
// centre). The pyramid's apex is singular (its map collapses the top face) and is left out.
const vec3f kCorners4[1] = {{0, 0, 0}};  // the tet's Jacobian is constant
const vec3f kCorners5[5] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 0.2f}};
const vec3f kCorners6[7] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1 / 3.f, 1 / 3.f, 0.5f}};
const vec3f kCorners8[9] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},         {0, 0, 1},
                            {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.5f, 0.5f, 0.5f}};

double jacobian_det(int n, const vec3d* x, const vec3f& pc) {
  float w[8];
  vec3f d[8];
  shape::weights(n, pc.x, pc.y, pc.z, w, d);
  vec3d jr(0.0), js(0.0), jt(0.0);
  for (int i = 0; i < n; ++i) {
    jr = jr + x[i] * double(d[i].x);
    js = js + x[i] * double(d[i].y);
    jt = jt + x[i] * double(d[i].z);
  }
  return dot(jr, cross(js, jt));
}

// +1 or -1: the sign of every corner's Jacobian; 0: degenerate; 2: tangled (mixed signs).
int element_orientation(int n, const vec3d* x) {
  const vec3f* corners = n == 4 ? kCorners4 : n == 5 ? kCorners5 : n == 6 ? kCorners6 : kCorners8;
  const int count = n == 4 ? 1 : n == 5 ? 5 : n + 1;  // corners (the pyramid's four) and the centre
  box3f b = box3f::make_empty();
  for (int i = 0; i < n; ++i) b.extend(vec3f(x[i]));
  const double extent = reduce_max(b.size());
  const double tiny = 1e-9 * extent * extent * extent;
  int positive = 0, negative = 0;
  for (int c = 0; c < count; ++c) {
    const double det = jacobian_det(n, x, corners[c]);
    if (std::fabs(det) <= tiny) return 0;
    (det > 0 ? positive : negative)++;
  }
  return positive && negative ? 2 : (positive ? 1 : -1);
}

std::string element_name(uint64_t e, int n) {
  return std::string(kTypeSlotNames[type_slot(n)]) + " " + std::to_string(e);
}

}  // namespace

WorldTransform mesh_transform(const MeshData& data) {
  Box3<double> b{vec3d(INFINITY), vec3d(-INFINITY)};
  for (const vec3d& p : data.points) b.extend(p);
  WorldTransform t;
  t.origin = b.lower;
  return t;
}

UMesh make_umesh(const MeshData& data, const WorldTransform& transform, const std::string& file) {
  check_mesh(data, file);
  input_check(data.points.size() < kNoVertex, file, "more than 2^32 - 1 points");
  input_check(data.cell_count() < kNoVertex, file, "more than 2^32 - 1 cells");  // elements are 32-bit ids
  UMesh m;
  m.vertices.resize(data.points.size());
  for (size_t i = 0; i < data.points.size(); ++i) m.vertices[i] = vec3f(transform.to_grid(data.points[i]));
  m.elements.resize(data.cell_count());
  // The elements and their orientations in parallel (a hex's is a dozen corner volumes); the
  // checks after them in order, so that a message names the first bad element as a serial loop
  // would.
  std::vector<int8_t> orientation(data.cell_count());
  parallel_for_ranges(
      int64_t(data.cell_count()),
      [&](int64_t begin, int64_t end) {
        for (auto e = uint64_t(begin); e < uint64_t(end); ++e) {
          UElement& el = m.elements[e];
          const uint64_t first = data.cell_offsets[e];
          const int n = int(data.cell_offsets[e + 1] - first);
          vec3d x[8];
          for (int k = 0; k < 8; ++k) el.v[k] = k < n ? uint32_t(data.connectivity[first + uint64_t(k)]) : kNoVertex;
          for (int k = 0; k < n; ++k) x[k] = data.points[el.v[k]] - transform.origin;
          orientation[e] = int8_t(element_orientation(n, x));
        }
      },
      4096);
  int64_t votes[4] = {};
  for (uint64_t e = 0; e < data.cell_count(); ++e) {
    const int n = m.elements[e].vertex_count(), o = orientation[e];
    if (o == 0) input_error(file, element_name(e, n) + " is degenerate (no volume)");
    if (o == 2) input_error(file, element_name(e, n) + " is tangled (inverted at some corners)");
    votes[type_slot(n)] += o;
    ++m.count_by_type[type_slot(n)];
  }
  for (uint64_t e = 0; e < data.cell_count(); ++e) {
    const int n = m.elements[e].vertex_count(), slot = type_slot(n);
    if (votes[slot] != 0 && (orientation[e] > 0) != (votes[slot] > 0))
      input_error(file, element_name(e, n) + " is inverted (its orientation is the opposite of most " +
                            kTypeSlotNames[slot] + " elements)");
  }
  return m;
}

std::vector<MeshFieldRef> mesh_fields(const MeshData& data) {
  std::vector<MeshFieldRef> out;
  auto taken = [&](const std::string& name) {
    for (const MeshFieldRef& f : out)
      if (f.name == name) return true;
    return false;
  };
  auto add = [&](const MeshArray& a, bool cell, size_t index) {
    std::string base = a.name.empty() ? "field" : a.name;
    if (taken(base)) base += cell ? "_cell" : "_point";
    out.push_back({base, cell, index, -1});
    if (a.components == 1) return;
    static const char* kAxes[3] = {"x", "y", "z"};
    for (int c = 0; c < a.components; ++c)
      out.push_back({base + "_" + (a.components <= 3 ? kAxes[c] : std::to_string(c)), cell, index, c});
  };
  for (size_t i = 0; i < data.point_data.size(); ++i) add(data.point_data[i], false, i);
  for (size_t i = 0; i < data.cell_data.size(); ++i) add(data.cell_data[i], true, i);
  return out;
}

namespace {
double tuple_value(const MeshArray& a, uint64_t tuple, int component) {
  const double* v = a.values.data() + tuple * uint64_t(a.components);
  if (component >= 0 || a.components == 1) return v[component >= 0 ? component : 0];
  double sum = 0;
  for (int c = 0; c < a.components; ++c) sum += v[c] * v[c];
  return std::sqrt(sum);
}
}  // namespace

PointCells point_cells_of(const MeshData& data) {
  PointCells pc;
  pc.offsets.assign(data.points.size() + 1, 0);
  for (uint64_t v : data.connectivity) ++pc.offsets[v + 1];
  for (size_t p = 0; p < data.points.size(); ++p) pc.offsets[p + 1] += pc.offsets[p];
  pc.cells.resize(data.connectivity.size());
  std::vector<uint64_t> next(pc.offsets.begin(), pc.offsets.end() - 1);
  for (uint64_t e = 0; e < data.cell_count(); ++e)
    for (uint64_t k = data.cell_offsets[e]; k < data.cell_offsets[e + 1]; ++k)
      pc.cells[next[data.connectivity[k]]++] = uint32_t(e);
  return pc;
}

std::vector<float> mesh_field_values(const MeshData& data, const MeshFieldRef& f, const PointCells* cells) {
  std::vector<float> out(data.points.size());
  if (!f.cell) {
    const MeshArray& a = data.point_data.at(f.array);
    for (uint64_t i = 0; i < out.size(); ++i) out[i] = float(tuple_value(a, i, f.component));
    return out;
  }
  const MeshArray& a = data.cell_data.at(f.array);
  std::optional<PointCells> own;
  if (!cells) cells = &own.emplace(point_cells_of(data));
  parallel_for_ranges(
      int64_t(out.size()),
      [&](int64_t begin, int64_t end) {
        for (auto p = uint64_t(begin); p < uint64_t(end); ++p) {
          // A cell without data (NaN: a solid's velocity) is left out of its points' means.
          double sum = 0.0;
          uint64_t count = 0;
          for (uint64_t k = cells->offsets[p]; k < cells->offsets[p + 1]; ++k) {
            const double v = tuple_value(a, cells->cells[k], f.component);
            if (std::isnan(v)) continue;
            sum += v;
            ++count;
          }
          out[p] = count ? float(sum / double(count)) : NAN;
        }
      },
      4096);
  return out;
}

void check_same_mesh(const MeshData& first, const MeshData& step, const std::string& file) {
  const bool same = first.points.size() == step.points.size() && first.cell_types == step.cell_types &&
                    first.connectivity == step.connectivity && first.points == step.points;
  if (!same)
    input_error(file, "this step's mesh differs from the first step's (" + std::to_string(step.points.size()) +
                          " points, " + std::to_string(step.cell_count()) + " cells; first step " +
                          std::to_string(first.points.size()) + " points, " + std::to_string(first.cell_count()) +
                          " cells): a time series must keep one mesh");
}

}  // namespace vs
