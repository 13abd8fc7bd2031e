#include "volstream/umesh/cell_rebuild.h"

#include <algorithm>

#include "volstream/core/error.h"

namespace vs {

bool arrays_match(const std::vector<MeshArray>& arrays, uint64_t tuples) {
  return std::all_of(arrays.begin(), arrays.end(), [&](const MeshArray& a) {
    return a.components >= 1 && a.values.size() == tuples * uint64_t(a.components);
  });
}

void check_rebuild_input(const MeshData& m, const char* what, const std::string& file) {
  input_check(m.cell_offsets.size() == m.cell_count() + 1 && m.cell_offsets.back() == m.connectivity.size(), file,
              std::string(what) + ": the cell offsets do not match the cells");
  for (uint64_t c = 0; c < m.cell_count(); ++c)
    input_check(m.cell_offsets[c] <= m.cell_offsets[c + 1], file, std::string(what) + ": the cell offsets decrease");
  input_check(arrays_match(m.point_data, m.points.size()) && arrays_match(m.cell_data, m.cell_count()), file,
              std::string(what) + ": a data array does not match the points or cells");
}

uint64_t CellRebuild::add_point(MeshData& m, std::span<const uint64_t> vertices, std::span<const double> weights) {
  if (added_vertices_.empty()) first_added_ = m.points.size();
  vec3d sum(0.0);
  for (size_t i = 0; i < vertices.size(); ++i) sum = sum + m.points[vertices[i]] * weights[i];
  m.points.push_back(sum);
  added_vertices_.insert(added_vertices_.end(), vertices.begin(), vertices.end());
  added_weights_.insert(added_weights_.end(), weights.begin(), weights.end());
  added_offsets_.push_back(added_vertices_.size());
  return m.points.size() - 1;
}

void CellRebuild::add(uint8_t type, std::span<const uint64_t> vertices, uint64_t from_cell) {
  types_.push_back(type);
  connectivity_.insert(connectivity_.end(), vertices.begin(), vertices.end());
  offsets_.push_back(connectivity_.size());
  source_.push_back(from_cell);
}

void CellRebuild::keep(const MeshData& m, uint64_t cell) {
  const uint64_t begin = m.cell_offsets[cell];
  add(m.cell_types[cell], std::span(m.connectivity).subspan(begin, m.cell_offsets[cell + 1] - begin), cell);
}

// In order, so that a point combined from points added before it finds their data.
void CellRebuild::add_point_data(std::vector<MeshArray>& point_data) const {
  if (added_vertices_.empty()) return;
  for (MeshArray& a : point_data) {
    const auto components = size_t(a.components);
    a.values.resize(first_added_ * components);
    for (size_t p = 0; p + 1 < added_offsets_.size(); ++p)
      for (size_t k = 0; k < components; ++k) {
        double total = 0.0;
        for (uint64_t i = added_offsets_[p]; i < added_offsets_[p + 1]; ++i)
          total += added_weights_[i] * a.values[added_vertices_[i] * components + k];
        a.values.push_back(total);
      }
  }
}

void CellRebuild::gather_cell_data(std::vector<MeshArray>& cell_data) const {
  for (MeshArray& a : cell_data) {
    const auto components = size_t(a.components);
    std::vector<double> values(source_.size() * components);
    double* out = values.data();
    for (uint64_t c : source_) out = std::copy_n(a.values.data() + c * components, components, out);
    a.values = std::move(values);
  }
}

void CellRebuild::finish_data(std::vector<MeshArray>& point_data, std::vector<MeshArray>& cell_data) const {
  add_point_data(point_data);
  gather_cell_data(cell_data);
}

void CellRebuild::finish(MeshData& m) const& {
  m.cell_types = types_;
  m.cell_offsets = offsets_;
  m.connectivity = connectivity_;
  finish_data(m.point_data, m.cell_data);
}

void CellRebuild::move_cells(MeshData& m) {
  m.cell_types = std::move(types_);
  m.cell_offsets = std::move(offsets_);
  m.connectivity = std::move(connectivity_);
}

void CellRebuild::finish(MeshData& m) && {
  move_cells(m);
  finish_data(m.point_data, m.cell_data);
}

namespace {

MeshData topology_of(const MeshData& m) {
  MeshData t;
  t.points = m.points;
  t.cell_types = m.cell_types;
  t.cell_offsets = m.cell_offsets;
  t.connectivity = m.connectivity;
  return t;
}

bool same_topology(const MeshData& a, const MeshData& b) {
  return a.cell_types == b.cell_types && a.cell_offsets == b.cell_offsets && a.connectivity == b.connectivity &&
         a.points.size() == b.points.size() &&
         std::equal(a.points.begin(), a.points.end(), b.points.begin(),
                    [](const vec3d& p, const vec3d& q) { return p.x == q.x && p.y == q.y && p.z == q.z; });
}

}  // namespace

bool SplitMemo::reuse(MeshData& m, SplitKey key, const std::string& file) const {
  if (!remembered_ || key.size() != key_.size() || !same_topology(m, source_)) return false;
  auto remembered = key_.begin();
  for (std::span<const std::byte> k : key) {
    if (!std::equal(k.begin(), k.end(), remembered->begin(), remembered->end())) return false;
    ++remembered;
  }
  check_rebuild_input(m, "a step split as the one before", file);
  m.points = split_points_;
  rebuild_.finish(m);
  return true;
}

void SplitMemo::split_begins(const MeshData& source, SplitKey key) {
  remembered_ = false;
  source_ = topology_of(source);
  key_.clear();
  for (std::span<const std::byte> k : key) key_.emplace_back(k.begin(), k.end());
}

void SplitMemo::split_ends(CellRebuild rebuild, const std::vector<vec3d>& points) {
  rebuild_ = std::move(rebuild);
  split_points_ = points;
  remembered_ = true;
}

}  // namespace vs
