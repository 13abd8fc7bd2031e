#include "volstream/umesh/mesh_pieces.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <string_view>

#include <tbb/parallel_sort.h>

#include "volstream/core/error.h"
#include "volstream/umesh/cell_rebuild.h"

namespace vs {
namespace {

constexpr std::string_view kGhostArray = "vtkGhostType";

bool same_layout(const std::vector<MeshArray>& a, const std::vector<MeshArray>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].name != b[i].name || a[i].components != b[i].components) return false;
  return true;
}

// Each piece's `arrays` (point or cell data, of `tuples(piece)` tuples) made the union of all
// pieces' in the order first met, those a piece lacks NaN (no data) on it; the arrays are then
// alike in every piece, unless one name comes with other components somewhere (which
// append_piece refuses).
template <class Tuples>
void give_every_piece_every_array(std::vector<MeshData>& pieces, std::vector<MeshArray> MeshData::*arrays,
                                  Tuples tuples) {
  std::vector<std::pair<std::string, int>> all;  // name, components
  for (const MeshData& p : pieces)
    for (const MeshArray& a : p.*arrays)
      if (std::find_if(all.begin(), all.end(), [&](const auto& n) { return n.first == a.name; }) == all.end())
        all.push_back({a.name, a.components});
  for (MeshData& p : pieces) {
    std::vector<MeshArray> ordered;
    for (const auto& named : all) {  // not bindings: clang 14's lambdas cannot capture them
      const auto it = std::find_if((p.*arrays).begin(), (p.*arrays).end(),
                                   [&](const MeshArray& a) { return a.name == named.first; });
      if (it != (p.*arrays).end())
        ordered.push_back(std::move(*it));
      else
        ordered.push_back({named.first, named.second, std::vector<double>(tuples(p) * uint64_t(named.second), NAN)});
    }
    p.*arrays = std::move(ordered);
  }
}

void append_arrays(std::vector<MeshArray>& to, const std::vector<MeshArray>& from) {
  for (size_t i = 0; i < to.size(); ++i)
    to[i].values.insert(to[i].values.end(), from[i].values.begin(), from[i].values.end());
}

// `piece` after `mesh`: its point indices and connectivity offsets move up.
void append_piece(MeshData& mesh, const MeshData& piece, size_t index, const std::string& origin) {
  if (!same_layout(mesh.point_data, piece.point_data) || !same_layout(mesh.cell_data, piece.cell_data))
    input_error(origin, "piece " + std::to_string(index) + " has other point or cell arrays than piece 0");
  const uint64_t point_base = mesh.points.size(), connectivity_base = mesh.connectivity.size();
  mesh.points.insert(mesh.points.end(), piece.points.begin(), piece.points.end());
  for (uint64_t v : piece.connectivity) mesh.connectivity.push_back(v + point_base);
  for (size_t i = 1; i < piece.cell_offsets.size(); ++i)
    mesh.cell_offsets.push_back(piece.cell_offsets[i] + connectivity_base);
  mesh.cell_types.insert(mesh.cell_types.end(), piece.cell_types.begin(), piece.cell_types.end());
  append_arrays(mesh.point_data, piece.point_data);
  append_arrays(mesh.cell_data, piece.cell_data);
}

// Removes the array named vtkGhostType from `arrays` and returns its values (empty if none).
std::vector<double> take_ghost_array(std::vector<MeshArray>& arrays) {
  const auto it = std::find_if(arrays.begin(), arrays.end(),
                               [](const MeshArray& a) { return a.name == kGhostArray && a.components == 1; });
  if (it == arrays.end()) return {};
  std::vector<double> values = std::move(it->values);
  arrays.erase(it);
  return values;
}

// Keeps the tuples i with keep[i] of every array.
void keep_tuples(std::vector<MeshArray>& arrays, const std::vector<bool>& keep) {
  for (MeshArray& a : arrays) {
    const size_t n = size_t(a.components);
    size_t out = 0;
    for (size_t i = 0; i < keep.size(); ++i)
      if (keep[i]) std::copy_n(a.values.begin() + i * n, n, a.values.begin() + out++ * n);
    a.values.resize(out * n);
  }
}

// Drops the ghost cells; true when any was dropped.
bool drop_ghost_cells(MeshData& m) {
  take_ghost_array(m.point_data);
  const std::vector<double> ghost = take_ghost_array(m.cell_data);
  std::vector<bool> keep(m.cell_count(), true);
  size_t dropped = 0;
  for (size_t c = 0; c < ghost.size() && c < keep.size(); ++c) {
    const double g = ghost[c];
    const uint8_t flags = g >= 0 && g < 256 ? uint8_t(g) : 0;
    keep[c] = (flags & (kGhostDuplicateCell | kGhostHiddenCell)) == 0;
    dropped += !keep[c];
  }
  if (dropped == 0) return false;
  CellRebuild cells;
  for (size_t c = 0; c < keep.size(); ++c)
    if (keep[c]) cells.keep(m, c);
  std::move(cells).finish(m);
  return true;
}

// The bits of point i's coordinates and point data, compared in that order.
class PointKeys {
 public:
  explicit PointKeys(const MeshData& m) : m_(m) {}
  int compare(uint64_t a, uint64_t b) const {
    for (int axis = 0; axis < 3; ++axis)
      if (int c = compare_bits(m_.points[a][axis], m_.points[b][axis])) return c;
    for (const MeshArray& array : m_.point_data)
      for (size_t k = 0, n = size_t(array.components); k < n; ++k)
        if (int c = compare_bits(array.values[a * n + k], array.values[b * n + k])) return c;
    return 0;
  }

 private:
  static int compare_bits(double x, double y) {
    const uint64_t a = std::bit_cast<uint64_t>(x), b = std::bit_cast<uint64_t>(y);
    return a < b ? -1 : a > b ? 1 : 0;
  }
  const MeshData& m_;
};

// Each connectivity entry pointed at the first of the points with its key.
void weld_points(MeshData& m) {
  std::vector<uint64_t> order(m.points.size());
  std::iota(order.begin(), order.end(), uint64_t(0));
  const PointKeys keys(m);
  tbb::parallel_sort(order.begin(), order.end(), [&](uint64_t a, uint64_t b) {
    const int c = keys.compare(a, b);
    return c != 0 ? c < 0 : a < b;  // the first point of equals leads its run
  });
  std::vector<uint64_t> same(m.points.size());
  for (size_t i = 0; i < order.size(); ++i)
    same[order[i]] = i > 0 && keys.compare(order[i - 1], order[i]) == 0 ? same[order[i - 1]] : order[i];
  for (uint64_t& v : m.connectivity) v = same[v];
}

}  // namespace

std::vector<bool> drop_unused_points(MeshData& m) {
  std::vector<bool> used(m.points.size(), false);
  for (uint64_t v : m.connectivity) used[v] = true;
  std::vector<uint64_t> index(m.points.size());
  uint64_t next = 0;
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i]) m.points[next] = m.points[i], index[i] = next++;
  m.points.resize(next);
  for (uint64_t& v : m.connectivity) v = index[v];
  keep_tuples(m.point_data, used);
  return used;
}

namespace {

// What the steps below index by, checked (each reader checks its own file, but a piece may come
// from any reader): offsets rising to the connectivity's end, indices in range, array sizes.
void check_structure(const MeshData& m, const std::string& origin) {
  const auto& offsets = m.cell_offsets;
  if (offsets.size() != m.cell_count() + 1 || offsets.front() != 0 || offsets.back() != m.connectivity.size() ||
      !std::is_sorted(offsets.begin(), offsets.end()))
    input_error(origin, "the pieces' cell offsets do not match their cells");
  for (uint64_t v : m.connectivity)
    if (v >= m.points.size()) input_error(origin, "a piece's connectivity entry is out of range");
  for (const auto& [arrays, tuples] : {std::pair{&m.point_data, m.points.size()}, {&m.cell_data, m.cell_count()}})
    for (const MeshArray& a : *arrays)
      if (a.components < 1 || a.values.size() != tuples * size_t(a.components))
        input_error(origin, "array '" + a.name + "' of the pieces has the wrong size");
}

// Cells [begin, end) of m as a piece with its own points (in first-use order), and `ghosts` more
// cells after them flagged as ghosts.
MeshData cut_piece(const MeshData& m, uint64_t begin, uint64_t end, uint64_t ghosts) {
  MeshData piece;
  constexpr uint64_t kNone = UINT64_MAX;
  std::vector<uint64_t> local(m.points.size(), kNone);  // the piece's index of a mesh point
  for (const MeshArray& a : m.point_data) piece.point_data.push_back({a.name, a.components, {}});
  for (const MeshArray& a : m.cell_data) piece.cell_data.push_back({a.name, a.components, {}});
  MeshArray ghost{std::string(kGhostArray), 1, {}};
  piece.cell_offsets = {0};
  const uint64_t last = std::min<uint64_t>(end + ghosts, m.cell_count());
  for (uint64_t c = begin; c < last; ++c) {
    for (uint64_t k = m.cell_offsets[c]; k < m.cell_offsets[c + 1]; ++k) {
      const uint64_t v = m.connectivity[k];
      if (local[v] == kNone) {
        local[v] = piece.points.size();
        piece.points.push_back(m.points[v]);
        for (size_t a = 0; a < m.point_data.size(); ++a) {
          const size_t n = size_t(m.point_data[a].components);
          for (size_t i = 0; i < n; ++i) piece.point_data[a].values.push_back(m.point_data[a].values[v * n + i]);
        }
      }
      piece.connectivity.push_back(local[v]);
    }
    piece.cell_offsets.push_back(piece.connectivity.size());
    piece.cell_types.push_back(m.cell_types[c]);
    for (size_t a = 0; a < m.cell_data.size(); ++a) {
      const size_t n = size_t(m.cell_data[a].components);
      for (size_t i = 0; i < n; ++i) piece.cell_data[a].values.push_back(m.cell_data[a].values[c * n + i]);
    }
    ghost.values.push_back(c >= end ? kGhostDuplicateCell : 0);
  }
  if (ghosts > 0) {
    piece.cell_data.push_back(ghost);
    piece.point_data.push_back({std::string(kGhostArray), 1, std::vector<double>(piece.points.size(), 0.0)});
  }
  return piece;
}

}  // namespace

MeshData join_pieces(std::vector<MeshData> pieces, const std::string& origin, MissingArrays missing) {
  // An empty piece (a rank with no cells) adds nothing, and may not declare the arrays at all.
  std::erase_if(pieces, [](const MeshData& p) { return p.points.empty() && p.cell_count() == 0; });
  if (pieces.empty()) input_error(origin, "every piece is empty");
  if (missing == MissingArrays::no_data) {
    give_every_piece_every_array(pieces, &MeshData::point_data, [](const MeshData& p) { return p.points.size(); });
    give_every_piece_every_array(pieces, &MeshData::cell_data, [](const MeshData& p) { return p.cell_count(); });
  }
  MeshData mesh = std::move(pieces.front());
  for (size_t i = 1; i < pieces.size(); ++i) {
    append_piece(mesh, pieces[i], i, origin);
    pieces[i] = MeshData();  // its memory back before the next
  }
  check_structure(mesh, origin);
  const bool ghosts_dropped = drop_ghost_cells(mesh);
  if (pieces.size() > 1) weld_points(mesh);
  if (pieces.size() > 1 || ghosts_dropped) drop_unused_points(mesh);
  return mesh;
}

std::vector<MeshData> cut_into_pieces(const MeshData& mesh, int count, uint64_t ghosts) {
  std::vector<MeshData> pieces;
  const uint64_t cells = mesh.cell_count();
  for (int i = 0; i < count; ++i)
    pieces.push_back(
        cut_piece(mesh, cells * uint64_t(i) / uint64_t(count), cells * uint64_t(i + 1) / uint64_t(count), ghosts));
  return pieces;
}

}  // namespace vs
