#include "volstream/umesh/cell_rebuild.h"

#include <algorithm>

#include "volstream/core/error.h"

namespace vs {

void check_rebuild_input(const MeshData& m, const char* what, const std::string& file) {
  input_check(m.cell_offsets.size() == m.cell_count() + 1 && m.cell_offsets.back() == m.connectivity.size(), file,
              std::string(what) + ": the cell offsets do not match the cells");
  for (uint64_t c = 0; c < m.cell_count(); ++c)
    input_check(m.cell_offsets[c] <= m.cell_offsets[c + 1], file, std::string(what) + ": the cell offsets decrease");
  const auto match = [](const std::vector<MeshArray>& arrays, uint64_t tuples) {
    return std::all_of(arrays.begin(), arrays.end(), [&](const MeshArray& a) {
      return a.components >= 1 && a.values.size() == tuples * uint64_t(a.components);
    });
  };
  input_check(match(m.point_data, m.points.size()) && match(m.cell_data, m.cell_count()), file,
              std::string(what) + ": a data array does not match the points or cells");
}

uint64_t add_combined_point(MeshData& m, std::span<const uint64_t> vertices, std::span<const double> weights) {
  vec3d sum(0.0);
  for (size_t i = 0; i < vertices.size(); ++i) sum = sum + m.points[vertices[i]] * weights[i];
  m.points.push_back(sum);
  for (MeshArray& a : m.point_data) {
    const auto components = size_t(a.components);
    for (size_t k = 0; k < components; ++k) {
      double total = 0.0;
      for (size_t i = 0; i < vertices.size(); ++i) total += weights[i] * a.values[vertices[i] * components + k];
      a.values.push_back(total);
    }
  }
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

void CellRebuild::finish(MeshData& m) {
  m.cell_types = std::move(types_);
  m.cell_offsets = std::move(offsets_);
  m.connectivity = std::move(connectivity_);
  for (MeshArray& a : m.cell_data) {
    const auto components = size_t(a.components);
    std::vector<double> values;
    values.reserve(source_.size() * components);
    for (uint64_t c : source_)
      values.insert(values.end(), a.values.begin() + int64_t(c * components),
                    a.values.begin() + int64_t((c + 1) * components));
    a.values = std::move(values);
  }
}

}  // namespace vs
