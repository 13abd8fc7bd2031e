// The macrocell grid walk (for_each_cell_along) against the brute force: every cell's box tested
// against the ray. The walk must give every cell the ray passes through, with the interval
// ray_box gives for that cell's box (what the region BVH it replaced gave), front to back.
// The macrocells' value ranges, from the pass over the elements and from the per-region vertex
// lists, against the brute force over every element box and every region. The step widths'
// ladder, and a mesh volume's intervals against the cells they merge.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "volstream/render/integrators/umesh_renderer.h"
#include "volstream/umesh/demo.h"
#include "volstream/umesh/from_mesh_data.h"
#include "volstream/umesh/macrocells.h"
#include "volstream/umesh/mesh_accel.h"
#include "volstream/volume/umesh_volume.h"

namespace vs {
namespace {

struct Crossing {
  uint64_t cell;
  float t0, t1;
};

MacroGrid test_grid() {
  MacroGrid g;
  g.bounds = {{-1.f, 0.f, 2.f}, {3.f, 1.5f, 2.9f}};
  g.dims = {7, 4, 3};
  for (int a = 0; a < 3; ++a) g.cell_size[a] = g.bounds.size()[a] / float(g.dims[a]);
  return g;
}

// cell_of and subcell_of clamp the quotient and truncate; the plain formula floors and then
// clamps. They agree everywhere: random points, cell faces, far and non-finite coordinates. The
// lanes forms (the macrocells' pass) give the same ints, and a subcell's cell is p's cell.
TEST(MacroGrid, CellOfIsTheFlooredQuotientClamped) {
  const MacroGrid g = test_grid();
  constexpr int n = MacroGrid::kSubcells;
  auto floored_clamped = [&](const vec3f& p, int per_cell) {
    vec3i c;
    for (int a = 0; a < 3; ++a) {
      const float i = std::floor(float(per_cell) * ((p[a] - g.bounds.lower[a]) / g.cell_size[a]));
      const int count = per_cell * g.dims[a];
      c[a] = i >= 0.f ? (i < float(count) ? int(i) : count - 1) : 0;
    }
    return c;
  };
  const MacroGrid::Lanes lanes = g.lanes();
  std::vector<float> coordinates = {NAN, INFINITY, -INFINITY, 1e30f, -1e30f, -0.f, 0.f};
  for (int a = 0; a < 3; ++a)
    for (int k = -1; k <= g.dims[a] + 1; ++k) {
      const float face = g.bounds.lower[a] + float(k) * g.cell_size[a];
      coordinates.insert(coordinates.end(), {face, std::nextafter(face, -INFINITY), std::nextafter(face, INFINITY)});
    }
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> around(-3.f, 6.f);
  for (int i = 0; i < 2000; ++i) coordinates.push_back(around(rng));
  std::uniform_int_distribution<size_t> pick(0, coordinates.size() - 1);
  for (int i = 0; i < 20000; ++i) {
    const vec3f p(coordinates[pick(rng)], coordinates[pick(rng)], coordinates[pick(rng)]);
    const vec3i got = g.cell_of(p), want = floored_clamped(p, 1);
    ASSERT_TRUE(got.x == want.x && got.y == want.y && got.z == want.z) << p.x << " " << p.y << " " << p.z;
    const vec3i sub = g.subcell_of(p), want_sub = floored_clamped(p, n);
    ASSERT_TRUE(sub.x == want_sub.x && sub.y == want_sub.y && sub.z == want_sub.z) << p.x << " " << p.y << " " << p.z;
    const simd::i4 sub_lanes = MacroGrid::subcell_of(lanes, p), cell_lanes = MacroGrid::cell_of(lanes, p);
    for (int a = 0; a < 3; ++a) {
      ASSERT_EQ(sub_lanes[a], sub[a]) << p.x << " " << p.y << " " << p.z;
      ASSERT_EQ(cell_lanes[a], got[a]);
      ASSERT_EQ(sub[a] / n, got[a]);
    }
  }
}

// A block of cells, [lo, hi] inclusive.
struct CellBlock {
  vec3i lo, hi;
};
CellBlock whole(const MacroGrid& g) { return {{0, 0, 0}, g.dims - vec3i(1, 1, 1)}; }

std::vector<Crossing> walked(const MacroGrid& g, const vec3f& org, const vec3f& dir) {
  std::vector<Crossing> out;
  for_each_cell_along(g, org, dir, [&](uint64_t cell, float t0, float t1) {
    out.push_back({cell, t0, t1});
    return true;
  });
  return out;
}
std::vector<Crossing> walked(const MacroGrid& g, const CellBlock& b, const vec3f& org, const vec3f& dir) {
  std::vector<Crossing> out;
  for_each_cell_along(g, b.lo, b.hi, org, dir, [&](uint64_t cell, float t0, float t1) {
    out.push_back({cell, t0, t1});
    return true;
  });
  return out;
}

// Cells of the block whose box the ray crosses over a positive length after t = 0, by entry.
std::vector<Crossing> brute_force(const MacroGrid& g, const CellBlock& block, const vec3f& org, const vec3f& dir) {
  const SlabRay ray(org, dir);
  std::vector<Crossing> out;
  for (int z = block.lo.z; z <= block.hi.z; ++z)
    for (int y = block.lo.y; y <= block.hi.y; ++y)
      for (int x = block.lo.x; x <= block.hi.x; ++x) {
        float t0, t1;
        ray_box(ray, g.cell_box({x, y, z}), t0, t1);
        t0 = std::max(t0, 0.f);
        if (t1 - t0 > 1e-5f) out.push_back({g.index({x, y, z}), t0, t1});
      }
  std::sort(out.begin(), out.end(), [](const Crossing& a, const Crossing& b) { return a.t0 < b.t0; });
  return out;
}

// Returns how many cells of the block the ray crosses.
size_t expect_same_crossings(const MacroGrid& g, const CellBlock& block, const std::vector<Crossing>& walk,
                             const vec3f& org, const vec3f& dir) {
  const std::vector<Crossing> expected = brute_force(g, block, org, dir);
  // The walk may add cells it only touches (zero length); it must hold every crossed one, once.
  std::vector<Crossing> long_ones;
  for (size_t i = 0; i < walk.size(); ++i) {
    if (i > 0) {
      EXPECT_GE(walk[i].t0, walk[i - 1].t1 - 1e-5f) << "not front to back";
    }
    if (walk[i].t1 - walk[i].t0 > 1e-5f) long_ones.push_back(walk[i]);
  }
  EXPECT_EQ(long_ones.size(), expected.size()) << "org " << org.x << "," << org.y << "," << org.z;
  for (size_t i = 0; i < std::min(expected.size(), long_ones.size()); ++i) {
    EXPECT_EQ(long_ones[i].cell, expected[i].cell);
    EXPECT_EQ(long_ones[i].t0, expected[i].t0);
    EXPECT_EQ(long_ones[i].t1, expected[i].t1);
  }
  return expected.size();
}
size_t expect_same_crossings(const MacroGrid& g, const vec3f& org, const vec3f& dir) {
  return expect_same_crossings(g, whole(g), walked(g, org, dir), org, dir);
}

// Ray i of a test: from anywhere (in the grid too) towards a point of the grid, every fifth
// parallel to a grid plane; false when its origin is too close to that point to aim.
bool test_ray(std::mt19937& rng, const MacroGrid& g, int i, vec3f& org, vec3f& dir) {
  std::uniform_real_distribution<float> u(-3.f, 5.f), inside(0.f, 1.f);
  org = vec3f(u(rng), u(rng) * 0.5f, 2.f + u(rng) * 0.3f);
  const vec3f target = g.bounds.lower + g.bounds.size() * vec3f(inside(rng), inside(rng), inside(rng));
  dir = target - org;
  if (i % 5 == 0) dir[i % 3] = 0.f;
  if (length(dir) < 1e-3f) return false;
  dir = normalize(dir);
  return true;
}

TEST(MacroGridWalk, EqualsEveryCellTestedFromOutsideAndInside) {
  const MacroGrid g = test_grid();
  std::mt19937 rng(7);
  size_t crossed = 0;
  vec3f org, dir;
  for (int i = 0; i < 2000; ++i)
    if (test_ray(rng, g, i, org, dir)) crossed += expect_same_crossings(g, org, dir);
  EXPECT_GT(crossed, 2000u) << "too few rays meet the grid to test the walk";
}

// Walked over a block of the grid's cells (a frame's visible ones), the walk gives the block's
// crossed cells with the same intervals as over the whole grid; an empty block gives none.
TEST(MacroGridWalk, OverABlockEqualsTheBlocksCellsTested) {
  const MacroGrid g = test_grid();
  std::mt19937 rng(11);
  size_t crossed = 0;
  vec3f org, dir;
  for (int i = 0; i < 2000; ++i) {
    CellBlock b;
    for (int a = 0; a < 3; ++a) {
      std::uniform_int_distribution<int> cell(0, g.dims[a] - 1);
      const int p = cell(rng), q = cell(rng);
      b.lo[a] = std::min(p, q), b.hi[a] = std::max(p, q);
    }
    if (test_ray(rng, g, i, org, dir)) crossed += expect_same_crossings(g, b, walked(g, b, org, dir), org, dir);
  }
  EXPECT_GT(crossed, 1000u) << "too few rays meet the blocks to test the walk";
  const CellBlock none{{2, 0, 0}, {1, 3, 2}};
  EXPECT_TRUE(walked(g, none, {-2.f, 0.7f, 2.4f}, {1.f, 0.f, 0.f}).empty());
}

TEST(MacroGridWalk, AxisRaysAlongCellFacesVisitEveryCellOnce) {
  const MacroGrid g = test_grid();
  const vec3f on_face = g.bounds.lower + g.cell_size * vec3f(2.f, 1.f, 1.f);
  for (int a = 0; a < 3; ++a)
    for (float sign : {1.f, -1.f}) {
      vec3f dir(0.f, 0.f, 0.f), org = on_face;
      dir[a] = sign;
      org[a] = sign > 0 ? g.bounds.lower[a] - 1.f : g.bounds.upper[a] + 1.f;
      const std::vector<Crossing> walk = walked(g, org, dir);
      std::vector<uint64_t> cells;
      for (const Crossing& c : walk) cells.push_back(c.cell);
      std::sort(cells.begin(), cells.end());
      EXPECT_EQ(std::unique(cells.begin(), cells.end()), cells.end()) << "a cell twice";
      EXPECT_EQ(walk.size(), size_t(g.dims[a])) << "one row of cells along axis " << a;
    }
}

TEST(MacroGridWalk, MissesAndStops) {
  const MacroGrid g = test_grid();
  EXPECT_TRUE(walked(g, {-5.f, -5.f, -5.f}, normalize(vec3f(-1.f, 0.f, 0.f))).empty());
  EXPECT_TRUE(walked(g, {10.f, 0.5f, 2.5f}, {1.f, 0.f, 0.f}).empty()) << "the grid lies behind the origin";
  int visited = 0;
  for_each_cell_along(g, {-2.f, 0.7f, 2.4f}, {1.f, 0.f, 0.f}, [&](uint64_t, float, float) { return ++visited < 3; });
  EXPECT_EQ(visited, 3);
}

UMesh demo_umesh(const std::string& name, uint64_t elements) {
  const MeshData data = make_mesh_demo({name, elements, 1}, 0);
  return make_umesh(data, mesh_transform(data), name);
}

// Random values with the odd ones a field may hold: NaN, infinities, both zeros.
std::vector<float> random_values(size_t count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-10.f, 10.f);
  std::vector<float> v(count);
  for (size_t i = 0; i < count; ++i) {
    const uint32_t pick = rng() % 100;
    v[i] = pick == 0 ? NAN : pick == 1 ? INFINITY : pick == 2 ? -INFINITY : pick == 3 ? -0.f : u(rng);
  }
  return v;
}

// Every region against every element: the vertices of the elements whose box overlaps its grid
// cell (the overlap test of the macrocells: the cells from cell_of of the box's corners).
std::vector<std::set<uint32_t>> brute_force_vertices(const UMesh& mesh, const MacroCells& m) {
  std::vector<std::set<uint32_t>> out(m.region_count());
  for (size_t r = 0; r < m.region_count(); ++r) {
    const uint64_t cell = m.cell_of_region[r];
    for (const UElement& e : mesh.elements) {
      const box3f b = element_box(mesh.vertices.data(), e);
      const vec3i lo = m.grid.cell_of(b.lower), hi = m.grid.cell_of(b.upper);
      bool overlaps = false;
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x) overlaps |= m.grid.index({x, y, z}) == cell;
      if (overlaps) out[r].insert(e.v, e.v + e.vertex_count());
    }
  }
  return out;
}

// The range of the finite values of each region's vertices.
std::vector<Range> brute_force_ranges(const std::vector<std::set<uint32_t>>& vertices, const float* values) {
  std::vector<Range> out(vertices.size(), Range{INFINITY, -INFINITY});
  for (size_t r = 0; r < vertices.size(); ++r)
    for (uint32_t v : vertices[r])
      if (std::isfinite(values[v])) out[r] = {std::min(out[r].lo, values[v]), std::max(out[r].hi, values[v])};
  return out;
}

void expect_same_ranges(const std::vector<Range>& got, const std::vector<Range>& want, const char* what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (size_t r = 0; r < want.size(); ++r) {
    EXPECT_EQ(got[r].lo, want[r].lo) << what << ", region " << r;
    EXPECT_EQ(got[r].hi, want[r].hi) << what << ", region " << r;
  }
}

class MacrocellRangesTest : public ::testing::TestWithParam<std::string> {};

TEST_P(MacrocellRangesTest, ElementPassAndVertexListsEqualTheBruteForce) {
  const UMesh mesh = demo_umesh(GetParam(), 4000);
  const MacroCells cells = build_macrocells(mesh);
  EXPECT_FALSE(region_vertices(mesh, cells, 1024).has_value()) << "over its budget";
  const RegionVertices lists = region_vertices(mesh, cells).value();
  const std::vector<std::set<uint32_t>> want_vertices = brute_force_vertices(mesh, cells);
  ASSERT_EQ(lists.first.size(), cells.region_count() + 1);
  for (size_t r = 0; r < cells.region_count(); ++r) {
    const std::vector<uint32_t> list(lists.vertex.begin() + int64_t(lists.first[r]),
                                     lists.vertex.begin() + int64_t(lists.first[r + 1]));
    EXPECT_EQ(std::set<uint32_t>(list.begin(), list.end()), want_vertices[r]) << "region " << r;
    EXPECT_EQ(list.size(), want_vertices[r].size()) << "a vertex twice in region " << r;
    EXPECT_TRUE(std::is_sorted(list.begin(), list.end())) << "region " << r << "'s list is not ascending";
  }
  for (uint32_t seed : {1u, 2u}) {
    const std::vector<float> values = random_values(mesh.vertices.size(), seed);
    const std::vector<Range> want = brute_force_ranges(want_vertices, values.data());
    expect_same_ranges(macrocell_ranges(mesh, cells, values.data()), want, "element pass");
    expect_same_ranges(macrocell_ranges(lists, values.data()), want, "vertex lists");
  }
}

// Stored lists (a dataset's, from a file) are checked against the mesh: its own pass; a list that
// misses a corner, an index past the vertices, a list out of order, offsets that do not add up
// or fit other macrocells are each refused with a reason. A vertex too many passes (it only
// widens a range, as a brute-force range check below shows: never narrower than the truth).
TEST_P(MacrocellRangesTest, StoredListsAreCheckedAgainstTheMesh) {
  const UMesh mesh = demo_umesh(GetParam(), 4000);
  const MacroCells cells = build_macrocells(mesh);
  const RegionVertices own = region_vertices(mesh, cells).value();
  EXPECT_EQ(region_vertices_fault(mesh, cells, own), "");
  const auto changed = [&](auto&& change) {
    std::vector<uint64_t> first(own.first.begin(), own.first.end());
    std::vector<uint32_t> vertex(own.vertex.begin(), own.vertex.end());
    change(first, vertex);
    return region_vertices_fault(mesh, cells, RegionVertices{std::move(first), std::move(vertex)});
  };
  const uint32_t n = uint32_t(mesh.vertices.size());
  const size_t regions = cells.region_count();
  // Region 0's list without its last vertex: every later offset moves down by one.
  EXPECT_NE(changed([](auto& first, auto& vertex) {
              vertex.erase(vertex.begin() + int64_t(first[1]) - 1);
              for (size_t r = 1; r < first.size(); ++r) --first[r];
            }).find("missing"),
            std::string::npos);
  EXPECT_NE(changed([&](auto& first, auto& vertex) { vertex[first[1] - 1] = n; }).find("not ascending"),
            std::string::npos);
  EXPECT_NE(changed([](auto&, auto& vertex) { std::swap(vertex[0], vertex[1]); }).find("not ascending"),
            std::string::npos);
  EXPECT_NE(changed([](auto& first, auto&) { first.back() -= 1; }).find("offsets"), std::string::npos);
  EXPECT_NE(changed([](auto& first, auto&) { std::swap(first[1], first[2]); }).find("decrease"), std::string::npos);
  EXPECT_NE(changed([](auto& first, auto&) { first.pop_back(); }).find("offsets"), std::string::npos);
  // A vertex of no element of region 0 added to its list (the last one that is not there).
  uint32_t extra = n;
  for (uint32_t v = n; v-- > 0 && extra == n;)
    if (!std::binary_search(own.vertex.begin(), own.vertex.begin() + int64_t(own.first[1]), v)) extra = v;
  std::vector<uint64_t> first(own.first.begin(), own.first.end());
  std::vector<uint32_t> vertex(own.vertex.begin(), own.vertex.end());
  vertex.insert(std::upper_bound(vertex.begin(), vertex.begin() + int64_t(first[1]), extra), extra);
  for (size_t r = 1; r < first.size(); ++r) ++first[r];
  const RegionVertices wider{std::move(first), std::move(vertex)};
  EXPECT_EQ(region_vertices_fault(mesh, cells, wider), "");
  const std::vector<float> values = random_values(mesh.vertices.size(), 5);
  const std::vector<Range> truth = macrocell_ranges(mesh, cells, values.data()),
                           got = macrocell_ranges(wider, values.data());
  for (size_t r = 0; r < regions; ++r) EXPECT_TRUE(got[r].lo <= truth[r].lo && got[r].hi >= truth[r].hi) << r;
}

// A renderer given lists reads its ranges from them from the first call: the element pass's.
TEST_P(MacrocellRangesTest, GivenListsGiveTheFirstFramesRanges) {
  const UMesh mesh = demo_umesh(GetParam(), 4000);
  UMeshRenderer renderer(mesh, WorldTransform{});
  const RegionVertices lists = region_vertices(mesh, renderer.macrocells()).value();
  renderer.take_region_vertices(lists);
  EXPECT_EQ(renderer.bytes().region_lists, lists.bytes());
  const std::vector<float> values = random_values(mesh.vertices.size(), 7);
  expect_same_ranges(renderer.ranges(values.data()), macrocell_ranges(mesh, renderer.macrocells(), values.data()),
                     "first frame");
  const RegionVertices other{std::vector<uint64_t>{0, 0}, std::vector<uint32_t>{}};
  EXPECT_THROW(renderer.take_region_vertices(other), std::logic_error);
}

// The compact encoding's lists hold local vertices: the same ranges as its element pass.
TEST_P(MacrocellRangesTest, CompactVertexListsEqualItsElementPass) {
  const UMesh mesh = demo_umesh(GetParam(), 4000);
  const CompactMesh compact = build_compact_mesh(mesh);
  const MacroCells cells = build_macrocells(compact);
  const std::vector<float> values = random_values(mesh.vertices.size(), 3);
  const std::vector<float> local = compact.gather(values.data());
  expect_same_ranges(macrocell_ranges(region_vertices(compact, cells).value(), local.data()),
                     macrocell_ranges(compact, cells, local.data()), "compact");
}

// A renderer's first call passes over the elements, later ones read the lists: each step's
// ranges are its own.
TEST_P(MacrocellRangesTest, EveryStepOfASeriesGetsItsOwnRanges) {
  const UMesh mesh = demo_umesh(GetParam(), 4000);
  UMeshRenderer renderer(mesh, WorldTransform{});
  for (uint32_t step = 0; step < 3; ++step) {
    const std::vector<float> values = random_values(mesh.vertices.size(), 10 + step);
    expect_same_ranges(renderer.ranges(values.data()), macrocell_ranges(mesh, renderer.macrocells(), values.data()),
                       "step");
  }
}

// Each macrocell's subcell mask against the brute force over every element's corner box: a
// subcell is marked exactly where some box's corners' subcells enclose it. And the point test:
// no point it rules out lies in any element's box (every box tested), and it rules out some of
// the points that no box holds where the mesh leaves part of its macrocells empty.
TEST_P(MacrocellRangesTest, SubcellMasksAreTheElementBoxesOverlaps) {
  const UMesh mesh = demo_umesh(GetParam(), 4000);
  const MacroCells cells = build_macrocells(mesh);
  ASSERT_EQ(cells.subcells.of_region.size(), cells.region_count());
  size_t partial = 0;
  const MacroGrid& g = cells.grid;
  constexpr int n = MacroGrid::kSubcells;
  const std::vector<box3f> boxes = element_boxes(mesh);
  for (size_t r = 0; r < cells.region_count(); ++r) {
    const vec3i cell = g.cell_at(cells.cell_of_region[r]);
    SubcellMask want;
    for (const box3f& b : boxes) {
      const vec3i lo = g.subcell_of(b.lower), hi = g.subcell_of(b.upper);
      for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
          for (int x = 0; x < n; ++x) {
            const vec3i s{cell.x * n + x, cell.y * n + y, cell.z * n + z};
            if (lo.x <= s.x && s.x <= hi.x && lo.y <= s.y && s.y <= hi.y && lo.z <= s.z && s.z <= hi.z)
              want.layer[z] |= 1ull << (x + n * y);
          }
    }
    const uint32_t index = cells.subcells.of_region[r];
    const bool all = std::all_of(want.layer, want.layer + n, [](uint64_t w) { return ~w == 0; });
    if (all) {
      EXPECT_EQ(index, SubcellOccupancy::kAllOccupied) << "macrocell " << r;
      continue;
    }
    ASSERT_EQ(index, partial) << "macrocell " << r;  // the masks in region order, one each
    EXPECT_TRUE(want == cells.subcells.masks[partial++]) << "macrocell " << r;
  }
  EXPECT_EQ(cells.subcells.masks.size(), partial);
  const SubcellOccupancy occupancy{g, cells.region_of_cell.data(), cells.subcells.of_region.data(),
                                   cells.subcells.masks.data()};
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(-0.05f, 1.05f);
  const vec3f size = g.bounds.size();
  size_t outside_boxes = 0, ruled_out = 0;
  for (int i = 0; i < 20000; ++i) {
    const vec3f p = g.bounds.lower + vec3f(unit(rng) * size.x, unit(rng) * size.y, unit(rng) * size.z);
    const bool in_a_box = std::any_of(boxes.begin(), boxes.end(), [&](const box3f& b) { return b.contains(p); });
    const bool out = occupancy.rules_out(p);
    if (out) {
      EXPECT_FALSE(in_a_box) << p.x << " " << p.y << " " << p.z;
    }
    outside_boxes += !in_a_box;
    ruled_out += out;
  }
  if (GetParam() != std::string("tets")) {
    EXPECT_GT(ruled_out, outside_boxes / 4);
  }
  // Subcells nest in cells: the cell of p's subcell is p's cell.
  for (int i = 0; i < 2000; ++i) {
    const vec3f p = g.bounds.lower + vec3f(unit(rng) * size.x, unit(rng) * size.y, unit(rng) * size.z);
    const vec3i s = g.subcell_of(p), c = g.cell_of(p);
    EXPECT_EQ(s.x / n, c.x);
    EXPECT_EQ(s.y / n, c.y);
    EXPECT_EQ(s.z / n, c.z);
  }
}

INSTANTIATE_TEST_SUITE_P(Demos, MacrocellRangesTest, ::testing::Values("tets", "mixed", "holes"));

TEST(StepWidthLadder, RoundsDownToEighthOctaves) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> exponent(-30.f, 30.f);
  for (int i = 0; i < 10000; ++i) {
    const float w = std::exp2(exponent(rng));
    const float l = ladder_width(w);
    EXPECT_LE(l, w);
    EXPECT_GT(l, w / std::exp2(0.125f) * (1.f - 1e-6f));
    EXPECT_EQ(ladder_width(l), l) << "a rung is its own rung";
    EXPECT_NEAR(std::log2(l) * 8.f, std::round(std::log2(l) * 8.f), 1e-3f);
  }
}

// A mesh volume's intervals are the runs of consecutive visible cells of one step width, front
// to back, named by the run's first cell (brute force: the cells the grid walk gives, joined).
TEST(MeshVolumeIntervals, AreTheRunsOfVisibleCellsOfOneWidth) {
  const UMesh mesh = demo_umesh("holes", 20000);
  const MacroCells cells = build_macrocells(mesh);
  std::vector<uint8_t> visible(cells.region_count());
  for (size_t r = 0; r < visible.size(); ++r) visible[r] = r % 7 != 3;  // some culled
  UMeshVolume volume;
  volume.visible = visible.data();
  volume.step_widths = cells.step_width.data();
  volume.grid = cells.grid;
  volume.region_of_cell = cells.region_of_cell.data();
  const box3f& b = cells.grid.bounds;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  size_t merged = 0, runs = 0;
  for (int i = 0; i < 500; ++i) {
    const vec3f org = b.lower - b.size() + 3.f * b.size() * vec3f(u(rng), u(rng), u(rng));
    const vec3f dir = normalize(b.lower + b.size() * vec3f(u(rng), u(rng), u(rng)) - org);
    std::vector<RayInterval> want;
    bool after_shown = false;  // the previous cell the walk gave was visible
    for_each_cell_along(cells.grid, org, dir, [&](uint64_t cell, float t0, float t1) {
      const int32_t r = cells.region_of_cell[cell];
      const bool shown = r >= 0 && visible[size_t(r)];
      if (shown && after_shown && cells.step_width[size_t(r)] == cells.step_width[want.back().region]) {
        want.back().t1 = t1, ++merged;
      } else if (shown) {
        want.push_back({uint32_t(r), t0, t1});
      }
      after_shown = shown;
      return true;
    });
    std::vector<RayInterval> got;
    volume.for_each_interval(org, dir, [&](const RayInterval& iv) { return got.push_back(iv), true; });
    ASSERT_EQ(got.size(), want.size()) << "ray " << i;
    for (size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].region, want[k].region);
      EXPECT_EQ(got[k].t0, want[k].t0);
      EXPECT_EQ(got[k].t1, want[k].t1);
    }
    runs += got.size();
  }
  EXPECT_GT(2 * merged, runs) << "too few cells merged to test the runs";
}

}  // namespace
}  // namespace vs
