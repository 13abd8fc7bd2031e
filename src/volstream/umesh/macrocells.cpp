#include "volstream/umesh/macrocells.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cfloat>
#include <cmath>
#include <mutex>
#include <numeric>
#include <span>
#include <stdexcept>
#include <utility>

#include <tbb/enumerable_thread_specific.h>

#include "volstream/backend/parallel.h"
#include "volstream/core/stopwatch.h"
#include "volstream/umesh/compact_store.h"

namespace vs {
namespace {

// Floats as unsigned integers in the same order, so that ranges grow with integer atomics.
uint32_t ordered(float f) {
  const uint32_t b = std::bit_cast<uint32_t>(f);
  return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}
float from_ordered(uint32_t u) { return std::bit_cast<float>((u & 0x80000000u) ? (u & 0x7fffffffu) : ~u); }

void atomic_min(uint32_t& slot, uint32_t v) {
  std::atomic_ref<uint32_t> a(slot);
  uint32_t cur = a.load(std::memory_order_relaxed);
  while (v < cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}
void atomic_max(uint32_t& slot, uint32_t v) {
  std::atomic_ref<uint32_t> a(slot);
  uint32_t cur = a.load(std::memory_order_relaxed);
  while (v > cur && !a.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

// Subcell rows first..last of a layer (a byte per row): all bits of those bytes.
uint64_t row_bytes(int first, int last) { return (~0ull >> (8 * (7 - last))) & (~0ull << (8 * first)); }

// Marks the subcells of each cell that a box overlaps in `masks` (per grid cell), from the
// subcells of its corners, lo and hi (MacroGrid::subcell_of). Neighbouring elements mostly mark
// subcells already marked: a cell's eight layers are read and compared without a loop over the
// box's rows and layers (their counts vary from box to box), and written only where some
// subcell is missing.
void occupy_subcells(const MacroGrid& g, const simd::i4& lo, const simd::i4& hi, std::vector<SubcellMask>& masks) {
  constexpr int n = MacroGrid::kSubcells;
  static_assert(n == 8, "a row of subcells is a byte, a layer a 64-bit word");
  const simd::i4 cell_lo = lo / n, cell_hi = hi / n;
  for (int z = cell_lo[2]; z <= cell_hi[2]; ++z)
    for (int y = cell_lo[1]; y <= cell_hi[1]; ++y)
      for (int x = cell_lo[0]; x <= cell_hi[0]; ++x) {
        // The box's places in this cell, per axis: an x run of bits, repeated in rows y of layers z.
        const simd::i4 origin = simd::i4{x, y, z, 0} * n, below = lo - origin, above = hi - origin;
        const simd::i4 first = below > 0 ? below : 0, last = above < n - 1 ? above : n - 1;
        const uint64_t row = (2ull << last[0]) - (1ull << first[0]);
        const uint64_t rows = (row * 0x0101010101010101ull) & row_bytes(first[1], last[1]);
        SubcellMask& mask = masks[g.index({x, y, z})];
        uint64_t missing = 0;
        for (int k = 0; k < n; ++k) {
          const uint64_t wanted = first[2] <= k && k <= last[2] ? rows : 0;
          missing |= wanted & ~std::atomic_ref<uint64_t>(mask.layer[k]).load(std::memory_order_relaxed);
        }
        if (missing == 0) continue;
        for (int k = first[2]; k <= last[2]; ++k)
          std::atomic_ref<uint64_t>(mask.layer[k]).fetch_or(rows, std::memory_order_relaxed);
      }
}

// Calls f(cell index) for every grid cell in [lo, hi].
template <typename F>
void for_each_cell(const MacroGrid& g, const vec3i& lo, const vec3i& hi, F&& f) {
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) f(g.index({x, y, z}));
}
// Calls f(cell index) for every grid cell the box overlaps.
template <typename F>
void for_each_cell(const MacroGrid& g, const box3f& b, F&& f) {
  for_each_cell(g, g.cell_of(b.lower), g.cell_of(b.upper), f);
}

// Values merged into the cells their boxes overlap (merge(a, b): their union, a min or a pair of
// them), one run of boxes with the same cells at a time: consecutive elements of a spatially
// sorted mesh mostly overlap the same cells, so store(cell, value) (the atomic part) runs once
// per cell and run instead of once per cell and element. One per task; flush() at its end.
template <typename Value, typename Merge, typename Store>
class CellRuns {
 public:
  CellRuns(const MacroGrid& grid, Merge merge, Store store) : grid_(grid), merge_(merge), store_(store) {}
  // The cells from lo to hi (lanes x, y, z and 0, as MacroGrid::cell_of gives them).
  void add_cells(const simd::i4& lo, const simd::i4& hi, const Value& v) {
    if (simd::all_equal(lo, lo_) && simd::all_equal(hi, hi_)) {
      value_ = merge_(value_, v);
      return;
    }
    flush();
    lo_ = lo, hi_ = hi, value_ = v;
  }
  void flush() {
    for_each_cell(grid_, {lo_[0], lo_[1], lo_[2]}, {hi_[0], hi_[1], hi_[2]}, [&](uint64_t c) { store_(c, value_); });
    lo_ = simd::i4{}, hi_ = simd::i4{} - 1;  // no cells
  }

 private:
  const MacroGrid& grid_;
  Merge merge_;
  Store store_;
  simd::i4 lo_{}, hi_ = simd::i4{} - 1;
  Value value_{};
};

}  // namespace

MacroGrid macro_grid(const box3f& bounds, uint64_t elements) {
  MacroGrid g;
  g.bounds = bounds;
  const vec3f size = vmax(g.bounds.size(), vec3f(1e-30f));
  // Cubic cells, about kElementsPerMacrocell elements each, at most 256 per axis.
  const double cells = std::max(1.0, double(elements) / kElementsPerMacrocell);
  const double edge = std::cbrt(double(size.x) * size.y * size.z / cells);
  for (int a = 0; a < 3; ++a) {
    // Clamped as a double: a stored grid's hostile bounds may ask for more cells than an int holds.
    const double n = std::ceil(double(size[a]) / edge);
    g.dims[a] = n >= 1.0 ? (n < 256.0 ? int(n) : 256) : 1;  // NaN (a degenerate box): one cell
    g.cell_size[a] = size[a] / float(g.dims[a]);
    if (!(g.cell_size[a] > 0.f)) g.cell_size[a] = 1.f;  // a flat mesh: one layer of cells
  }
  return g;
}

bool box_touches(const MacroGrid& grid, const box3f& box, const std::vector<uint8_t>& cells) {
  uint8_t hit = 0;
  for_each_cell(grid, box, [&](uint64_t c) { hit |= cells[c]; });
  return hit != 0;
}

box3f MacroCells::box(size_t region) const { return grid.cell_box(grid.cell_at(cell_of_region[region])); }

// A step width rounded down to the ladder of eighth octaves (at most 9% finer than asked):
// neighbouring macrocells of about one element size get exactly one width, and a ray marches a
// run of them as one interval (volume/umesh_volume.h).
float ladder_width(float width) {
  // log2f may round across a rung either way: the rung is the largest power at most width.
  float rung = floorf(log2f(width) * 8.f);
  if (exp2f(rung / 8.f) > width) rung -= 1.f;
  if (exp2f((rung + 1.f) / 8.f) <= width) rung += 1.f;
  return exp2f(rung / 8.f);
}

namespace {

// The cube of an element's feature size: its box's volume, at least (1/1000 of its largest
// extent)^3 (a flat, axis-aligned element has a box of no volume), as a float at most FLT_MAX.
// A macrocell's step width is the cube root of the smallest of these: one root per cell.
float element_size_cubed(const box3f& b) {
  const vec3d s(b.size());  // double: the product of three large extents overflows a float
  const double floor = 1e-3 * reduce_max(s);
  return float(std::min(std::max(s.x * s.y * s.z, floor * floor * floor), double(FLT_MAX)));
}

// The union of the element boxes visit_elements gives (see build_over), and their count.
template <typename ElementsOf>
box3f bounds_over(int64_t items, uint64_t& elements, ElementsOf&& visit_elements) {
  box3f bounds = box3f::make_empty();
  std::mutex merge;
  elements = 0;
  parallel_for_ranges(
      items,
      [&](int64_t begin, int64_t end) {
        box3f b = box3f::make_empty();
        uint64_t n = 0;
        for (int64_t item = begin; item < end; ++item)
          visit_elements(item, [&](const box3f& box, const uint32_t*, int) { b.extend(box), ++n; });
        const std::lock_guard<std::mutex> lock(merge);
        bounds.extend(b);
        elements += n;
      },
      1024);
  return bounds;
}

// The grid over the elements' boxes (or `grid`) and the non-empty cells with their smallest
// element's size. visit_elements(item, add) calls add(box, vertex indices, vertex count) for the
// elements of one item of work (an element, a leaf: elements_of below), items in parallel; no
// array of all boxes is made, so the load's peak memory is the encoding's. On a given grid it is
// one pass over the elements, which also gives their boxes' union (`seen`).
template <typename ElementsOf>
MacroCells build_over(int64_t items, const MacroGrid* grid, box3f* seen, ElementsOf&& visit_elements) {
  MacroCells m;
  if (grid) {
    m.grid = *grid;
  } else {
    uint64_t elements = 0;
    const box3f bounds = bounds_over(items, elements, visit_elements);
    m.grid = macro_grid(bounds, elements);
  }
  const uint64_t n = m.grid.cell_count();
  std::vector<uint32_t> finest(n, ordered(INFINITY));  // the smallest element_size_cubed
  const auto min_of = [](uint32_t a, uint32_t b) { return std::min(a, b); };
  const auto store = [&](uint64_t c, uint32_t cubed) { atomic_min(finest[c], cubed); };
  std::vector<SubcellMask> subcells(n);  // per grid cell
  box3f bounds = box3f::make_empty();
  std::mutex merge;
  const MacroGrid::Lanes lanes = m.grid.lanes();
  const Stopwatch watch;
  parallel_for_ranges(
      items,
      [&](int64_t begin, int64_t end) {
        box3f b = box3f::make_empty();
        CellRuns<uint32_t, decltype(min_of), decltype(store)> runs(m.grid, min_of, store);
        for (int64_t item = begin; item < end; ++item)
          visit_elements(item, [&](const box3f& box, const uint32_t*, int) {
            b.extend(box);
            // One quotient per corner for both: the cell of a subcell is subcell / kSubcells.
            const simd::i4 lo = MacroGrid::subcell_of(lanes, box.lower), hi = MacroGrid::subcell_of(lanes, box.upper);
            runs.add_cells(lo / MacroGrid::kSubcells, hi / MacroGrid::kSubcells, ordered(element_size_cubed(box)));
            occupy_subcells(m.grid, lo, hi, subcells);
          });
        runs.flush();
        const std::lock_guard<std::mutex> lock(merge);
        bounds.extend(b);
      },
      1024);
  launch_times().add("macrocell sizes", watch.seconds());
  if (seen) *seen = bounds;
  m.region_of_cell.assign(n, -1);
  for (uint64_t c = 0; c < n; ++c) {
    if (finest[c] == ordered(INFINITY)) continue;  // no element overlaps it
    m.region_of_cell[c] = int32_t(m.cell_of_region.size());
    m.cell_of_region.push_back(uint32_t(c));
    m.step_width.push_back(ladder_width(std::max(cbrtf(from_ordered(finest[c])), m.min_step())));
    const SubcellMask& mask = subcells[c];
    const bool all = std::all_of(mask.layer, mask.layer + MacroGrid::kSubcells, [](uint64_t w) { return ~w == 0; });
    m.subcells.of_region.push_back(all ? SubcellOccupancy::kAllOccupied : uint32_t(m.subcells.masks.size()));
    if (!all) m.subcells.masks.push_back(mask);
  }
  return m;
}

// A grid cell as bytes x, y, z and 0: a grid has at most 256 cells per axis (macro_grid; a stored
// grid is checked to be macro_grid's, mesh_index.cpp).
typedef uint8_t CellBytes __attribute__((vector_size(4)));
simd::i4 lanes_of(const CellBytes& c) { return __builtin_convertvector(c, simd::i4); }

// Each vertex's grid cell. MacroGrid::cell_of is monotonic in each axis, so the cells of an
// element's box (from the cell of its lower corner to that of its upper one) run from the
// smallest to the largest of its corners' cells, axis by axis: the ranges find an element's cells
// from its corners' with a few byte minima, without its box.
std::vector<CellBytes> vertex_cells(const MacroGrid& grid, std::span<const vec3f> vertices) {
  if (reduce_max(grid.dims) > 256) throw std::logic_error("vertex_cells: more than 256 cells per axis");
  std::vector<CellBytes> cells(vertices.size());
  const MacroGrid::Lanes lanes = grid.lanes();
  parallel_for_ranges(
      int64_t(vertices.size()),
      [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i)
          cells[size_t(i)] = __builtin_convertvector(MacroGrid::cell_of(lanes, vertices[size_t(i)]), CellBytes);
      },
      4096);
  return cells;
}

// The ranges over an encoding's elements (visit_corners(item, add) calls add(vertex indices,
// vertex count) for the elements of one item, as elements_of below without their boxes).
template <typename CornersOf>
std::vector<Range> ranges_over(const MacroCells& m, std::span<const vec3f> vertices, int64_t items, const float* values,
                               CornersOf&& visit_corners) {
  std::vector<uint32_t> lo(m.region_count(), ordered(INFINITY)), hi(m.region_count(), ordered(-INFINITY));
  using Ordered = std::pair<uint32_t, uint32_t>;  // a range as ordered integers
  const auto union_of = [](const Ordered& a, const Ordered& b) {
    return Ordered{std::min(a.first, b.first), std::max(a.second, b.second)};
  };
  const auto store = [&](uint64_t c, const Ordered& range) {
    const int32_t r = m.region_of_cell[c];
    if (r < 0) return;  // cannot happen for the mesh the cells were built from; never index -1
    atomic_min(lo[size_t(r)], range.first);
    atomic_max(hi[size_t(r)], range.second);
  };
  const Stopwatch watch;
  const std::vector<CellBytes> cell = vertex_cells(m.grid, vertices);
  parallel_for_ranges(
      items,
      [&](int64_t begin, int64_t end) {
        CellRuns<Ordered, decltype(union_of), decltype(store)> runs(m.grid, union_of, store);
        for (int64_t item = begin; item < end; ++item)
          visit_corners(item, [&](const uint32_t* vertex, int n) {
            CellBytes first = cell[vertex[0]], last = first;
            float elo = INFINITY, ehi = -INFINITY;
            for (int k = 0; k < n; ++k) {
              const CellBytes c = cell[vertex[k]];
              first = first < c ? first : c, last = last > c ? last : c;
              const float v = values[vertex[k]];
              if (std::isfinite(v)) elo = std::min(elo, v), ehi = std::max(ehi, v);
            }
            if (elo <= ehi) runs.add_cells(lanes_of(first), lanes_of(last), {ordered(elo), ordered(ehi)});
          });
        runs.flush();
      },
      1024);
  launch_times().add("macrocell ranges", watch.seconds());
  std::vector<Range> ranges(m.region_count());
  for (size_t r = 0; r < ranges.size(); ++r) ranges[r] = {from_ordered(lo[r]), from_ordered(hi[r])};
  return ranges;
}

// Calls f(region, vertex indices, vertex count) for every overlap of an element and a region, in
// parallel (visit_elements as for build_over).
template <typename ElementsOf, typename F>
void for_each_overlap(const MacroCells& m, int64_t items, ElementsOf&& visit_elements, F&& f) {
  parallel_for("region vertices", items, [&](int64_t item) {
    visit_elements(item, [&](const box3f& box, const uint32_t* vertex, int n) {
      for_each_cell(m.grid, box, [&](uint64_t c) {
        const int32_t r = m.region_of_cell[c];
        if (r >= 0) f(size_t(r), vertex, n);  // r < 0 cannot happen for the cells' own mesh
      });
    });
  });
}

// Each overlap's corners are counted per region and written into the region's slice; then each
// slice keeps the first of its repeats (a per-thread stamp per vertex: the region that last kept
// it), in the order the overlaps wrote them.
template <typename ElementsOf>
std::optional<RegionVertices> region_vertices_over(const MacroCells& m, int64_t items, size_t vertex_count,
                                                   uint64_t budget, ElementsOf&& visit_elements) {
  const Stopwatch watch;
  const size_t regions = m.region_count();
  std::vector<uint64_t> slice(regions + 1, 0);
  for_each_overlap(m, items, visit_elements, [&](size_t r, const uint32_t*, int n) {
    std::atomic_ref<uint64_t>(slice[r + 1]).fetch_add(uint64_t(n), std::memory_order_relaxed);
  });
  std::partial_sum(slice.begin(), slice.end(), slice.begin());
  if (slice.back() > budget / sizeof(uint32_t)) return std::nullopt;
  std::vector<uint32_t> all(slice.back());
  std::vector<uint64_t> cursor(slice.begin(), slice.end() - 1);
  for_each_overlap(m, items, visit_elements, [&](size_t r, const uint32_t* vertex, int n) {
    const uint64_t at = std::atomic_ref<uint64_t>(cursor[r]).fetch_add(uint64_t(n), std::memory_order_relaxed);
    std::copy(vertex, vertex + n, all.begin() + int64_t(at));
  });
  std::vector<uint64_t> first(regions + 1, 0);
  tbb::enumerable_thread_specific<std::vector<uint32_t>> stamps(vertex_count, 0u);
  parallel_for("region vertices", int64_t(regions), [&](int64_t r) {
    std::vector<uint32_t>& stamp = stamps.local();
    const uint32_t mark = uint32_t(r) + 1;
    uint64_t kept = slice[size_t(r)];
    for (uint64_t k = slice[size_t(r)]; k < slice[size_t(r) + 1]; ++k) {
      const uint32_t v = all[k];
      if (stamp[v] == mark) continue;
      stamp[v] = mark;
      all[kept++] = v;
    }
    // Ascending: one list whatever order the threads wrote the overlaps in (convert stores them),
    // and a region's values read in memory order.
    std::sort(all.begin() + int64_t(slice[size_t(r)]), all.begin() + int64_t(kept));
    first[size_t(r) + 1] = kept - slice[size_t(r)];
  });
  std::partial_sum(first.begin(), first.end(), first.begin());
  std::vector<uint32_t> vertex(first.back());
  parallel_for("region vertices", int64_t(regions), [&](int64_t r) {
    std::copy_n(all.begin() + int64_t(slice[size_t(r)]), first[size_t(r) + 1] - first[size_t(r)],
                vertex.begin() + int64_t(first[size_t(r)]));
  });
  launch_times().add("region vertex lists", watch.seconds());
  return RegionVertices{std::move(first), std::move(vertex)};
}

// Each encoding's elements as the macrocells read them: items of work (an element, a leaf), each
// calling add(vertex indices, vertex count) for its elements (corners_of), or add(box, vertex
// indices, vertex count) (elements_of).
auto corners_of(const UMesh& mesh) {
  return [&mesh](int64_t i, auto&& add) {
    const UElement& e = mesh.elements[size_t(i)];
    add(e.v, e.vertex_count());
  };
}
auto corners_of(const CompactMesh& mesh) {
  return [&mesh, view = view_of(mesh)](int64_t l, auto&& add) {
    for_each_element_of_leaf(mesh, view, uint32_t(l), [&](const CompactElement& e) { add(e.vertex, e.n); });
  };
}
template <typename Mesh>
auto elements_of(const Mesh& mesh) {
  return [corners = corners_of(mesh), vertices = mesh.vertices.data()](int64_t item, auto&& add) {
    corners(item, [&](const uint32_t* vertex, int n) {
      add(corners_box(n, [&](int i) -> const vec3f& { return vertices[vertex[i]]; }), vertex, n);
    });
  };
}

}  // namespace

MacroCells build_macrocells(const UMesh& mesh, const MacroGrid* grid, box3f* seen) {
  return build_over(int64_t(mesh.elements.size()), grid, seen, elements_of(mesh));
}
MacroCells build_macrocells(const CompactMesh& mesh, const MacroGrid* grid, box3f* seen) {
  return build_over(int64_t(mesh.leaves.size()), grid, seen, elements_of(mesh));
}

namespace {
template <typename Mesh>
std::vector<vec3d> centroids_of(const Mesh& mesh, std::span<const vec3f> vertices, int64_t items) {
  std::vector<vec3d> out;
  const auto visit = elements_of(mesh);
  for (int64_t item = 0; item < items; ++item)
    visit(item, [&](const box3f&, const uint32_t* vertex, int n) {
      vec3d sum(0.0);
      for (int k = 0; k < n; ++k) sum = sum + vec3d(vertices[vertex[k]]);
      out.push_back(sum / double(n));
    });
  return out;
}

}  // namespace

std::vector<vec3d> element_centroids(const UMesh& mesh) {
  return centroids_of(mesh, mesh.vertices, int64_t(mesh.elements.size()));
}
std::vector<vec3d> element_centroids(const CompactMesh& mesh) {
  return centroids_of(mesh, mesh.vertices, int64_t(mesh.leaves.size()));
}

std::vector<Range> macrocell_ranges(const UMesh& mesh, const MacroCells& m, const float* values) {
  return ranges_over(m, mesh.vertices, int64_t(mesh.elements.size()), values, corners_of(mesh));
}

std::vector<Range> macrocell_ranges(const CompactMesh& mesh, const MacroCells& m, const float* local_values) {
  return ranges_over(m, mesh.vertices, int64_t(mesh.leaves.size()), local_values, corners_of(mesh));
}

std::optional<RegionVertices> region_vertices(const UMesh& mesh, const MacroCells& m, uint64_t budget) {
  return region_vertices_over(m, int64_t(mesh.elements.size()), mesh.vertices.size(), budget, elements_of(mesh));
}
std::optional<RegionVertices> region_vertices(const CompactMesh& mesh, const MacroCells& m, uint64_t budget) {
  return region_vertices_over(m, int64_t(mesh.leaves.size()), mesh.vertices.size(), budget, elements_of(mesh));
}

namespace {
// The offsets and lists' own order (region_vertices_fault's first part); empty when they hold.
std::string region_lists_fault(const RegionVertices& lists, size_t regions, size_t vertex_count) {
  const HostArray<uint64_t>& first = lists.first;
  if (first.size() != regions + 1)
    return "holds " + std::to_string(first.size()) + " offsets for " + std::to_string(regions) +
           " macrocells (one more than they)";
  if (first[0] != 0 || first[regions] != lists.vertex.size())
    return "its offsets do not run from 0 to its " + std::to_string(lists.vertex.size()) + " entries";
  for (size_t r = 0; r < regions; ++r)
    if (first[r] > first[r + 1]) return "the offsets decrease at macrocell " + std::to_string(r);
  const int64_t bad = first_failing(
      int64_t(regions),
      [&](int64_t r) {
        const uint64_t begin = first[size_t(r)], end = first[size_t(r) + 1];
        bool ok = begin == end || lists.vertex[begin] < vertex_count;
        for (uint64_t k = begin + 1; k < end; ++k)
          ok &= lists.vertex[k - 1] < lists.vertex[k] && lists.vertex[k] < vertex_count;
        return ok;
      },
      64);
  if (bad >= 0) return "the list of macrocell " + std::to_string(bad) + " is not ascending vertices of the mesh";
  return {};
}
}  // namespace

std::string region_vertices_fault(const UMesh& mesh, const MacroCells& m, const RegionVertices& lists) {
  if (std::string fault = region_lists_fault(lists, m.region_count(), mesh.vertices.size()); !fault.empty())
    return fault;
  // The lists turned around: per vertex, the regions whose list holds it (ascending), so that
  // each corner's test scans the one or few regions of its vertex (a binary search in the
  // region's list took 3x as long: its branches and the lists' cache lines).
  std::vector<uint32_t> start(mesh.vertices.size() + 1, 0);
  for (uint32_t v : lists.vertex) ++start[v + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<uint32_t> cursor(start.begin(), start.end() - 1), region_of_entry(lists.vertex.size());
  for (size_t r = 0; r < m.region_count(); ++r)
    for (uint64_t k = lists.first[r]; k < lists.first[r + 1]; ++k)
      region_of_entry[cursor[lists.vertex[k]]++] = uint32_t(r);
  const auto listed = [&](int32_t r, uint32_t v) {
    bool found = false;
    for (uint32_t k = start[v]; k < start[v + 1]; ++k) found |= region_of_entry[k] == uint32_t(r);
    return found;
  };
  const auto visit = elements_of(mesh);
  const int64_t bad = first_failing(int64_t(mesh.elements.size()), [&](int64_t e) {
    bool ok = true;
    visit(e, [&](const box3f& box, const uint32_t* corner, int n) {
      for_each_cell(m.grid, box, [&](uint64_t c) {
        for (int k = 0; k < n; ++k) ok &= listed(m.region_of_cell[c], corner[k]);
      });
    });
    return ok;
  });
  if (bad >= 0) return "a corner of element " + std::to_string(bad) + " is missing from a macrocell's list";
  return {};
}

// The order of ranges_over's merges (ordered integers), so that the ranges are the same floats.
std::vector<Range> macrocell_ranges(const RegionVertices& lists, const float* values) {
  std::vector<Range> ranges(lists.first.empty() ? 0 : lists.first.size() - 1);
  parallel_for("macrocell ranges", int64_t(ranges.size()), [&](int64_t r) {
    uint32_t lo = ordered(INFINITY), hi = ordered(-INFINITY);
    for (uint64_t k = lists.first[size_t(r)]; k < lists.first[size_t(r) + 1]; ++k) {
      const float v = values[lists.vertex[k]];
      if (std::isfinite(v)) lo = std::min(lo, ordered(v)), hi = std::max(hi, ordered(v));
    }
    ranges[size_t(r)] = {from_ordered(lo), from_ordered(hi)};
  });
  return ranges;
}

}  // namespace vs
