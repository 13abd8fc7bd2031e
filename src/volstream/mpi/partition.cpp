#include "volstream/mpi/partition.h"

#include <algorithm>
#include <cmath>

#include "volstream/core/error.h"

namespace vs {
namespace {

constexpr double kInf = INFINITY;

// The cell indices i in [0, n) with lower + i * w in [lo, hi).
uint64_t indices_in(int32_t lower, int32_t w, int32_t n, double lo, double hi) {
  const double first = std::max(0.0, std::ceil((lo - lower) / w));
  const double end = std::min(double(n), std::ceil((hi - lower) / w));
  return end > first ? uint64_t(end - first) : 0;
}

struct Builder {
  const std::vector<Brick>& bricks;
  int32_t max_level = 0;
  Box3<double> data;  // grid bounds of all cells
  Partition out;

  double cost(const Box3<double>& region) const {
    double c = 0;
    for (const Brick& b : bricks) c += double(cells_in(b, region)) * cell_cost(b.level, max_level);
    return c;
  }

  // The coarse-cell face along `axis` that best gives the left side `share` of the cost.
  double split_plane(const Box3<double>& region, int axis, double share) const {
    const double w = double(level_width(max_level));
    const double lo = std::max(region.lower[axis], data.lower[axis]);
    const double hi = std::min(region.upper[axis], data.upper[axis]);
    int64_t a = int64_t(std::ceil(lo / w)), b = int64_t(std::floor(hi / w));  // candidate planes a*w .. b*w
    if (a > b) return lo;
    const double total = cost(region);
    auto left_cost = [&](int64_t k) {
      Box3<double> left = region;
      left.upper[axis] = double(k) * w;
      return cost(left);
    };
    while (a < b) {  // the first plane with at least `share` on its left
      const int64_t m = a + (b - a) / 2;
      if (left_cost(m) < share * total)
        a = m + 1;
      else
        b = m;
    }
    // The one before may be closer to the share.
    if (a > int64_t(std::ceil(lo / w)) &&
        std::fabs(left_cost(a - 1) - share * total) < std::fabs(left_cost(a) - share * total))
      --a;
    return double(a) * w;
  }

  int build(const Box3<double>& region, int first_rank, int count) {
    const int index = int(out.nodes.size());
    out.nodes.push_back({-1, 0, -1, -1, first_rank, count});
    if (count == 1) {
      out.regions[size_t(first_rank)] = region;
      return index;
    }
    // The longest side of the data inside the region.
    vec3d extent;
    for (int a = 0; a < 3; ++a)
      extent[a] = std::min(region.upper[a], data.upper[a]) - std::max(region.lower[a], data.lower[a]);
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const int left_count = count / 2;
    const double plane = split_plane(region, axis, double(left_count) / count);
    Box3<double> left = region, right = region;
    left.upper[axis] = right.lower[axis] = plane;
    const int l = build(left, first_rank, left_count);
    const int r = build(right, first_rank + left_count, count - left_count);
    PartitionNode& node = out.nodes[size_t(index)];
    node.axis = axis;
    node.plane = plane;
    node.left = l;
    node.right = r;
    return index;
  }
};

void visit_front_to_back(const Partition& p, int node, const vec3d& eye, const vec3d& dir, bool ortho,
                         std::vector<int>& order) {
  const PartitionNode& n = p.nodes[size_t(node)];
  if (n.axis < 0) {
    order.push_back(n.first_rank);
    return;
  }
  const bool left_first = ortho ? dir[n.axis] >= 0 : eye[n.axis] < n.plane;
  visit_front_to_back(p, left_first ? n.left : n.right, eye, dir, ortho, order);
  visit_front_to_back(p, left_first ? n.right : n.left, eye, dir, ortho, order);
}

bool reaches(const box3f& a, const Box3<double>& g) {
  for (int i = 0; i < 3; ++i)
    if (double(a.lower[i]) > g.upper[i] || double(a.upper[i]) < g.lower[i]) return false;
  return true;
}

}  // namespace

double cell_cost(int32_t level, int32_t max_level) {
  const double r = std::ldexp(1.0, level - max_level);
  return 1.0 + r * r;
}

uint64_t cells_in(const Brick& b, const Box3<double>& region) {
  const int32_t w = b.width();
  return indices_in(b.lower.x, w, b.dims.x, region.lower.x, region.upper.x) *
         indices_in(b.lower.y, w, b.dims.y, region.lower.y, region.upper.y) *
         indices_in(b.lower.z, w, b.dims.z, region.lower.z, region.upper.z);
}

Partition partition_bricks(const std::vector<Brick>& bricks, int ranks) {
  if (ranks < 1) throw UsageError("a partition needs at least one rank");
  Builder b{bricks, 0, Box3<double>::make_empty(), {}};
  for (const Brick& br : bricks) {
    b.max_level = std::max(b.max_level, br.level);
    const box3i c = br.cell_box();
    b.data.extend(Box3<double>{vec3d(c.lower), vec3d(c.upper)});
  }
  b.out.regions.resize(size_t(ranks));
  b.build({vec3d(-kInf), vec3d(kInf)}, 0, ranks);
  return std::move(b.out);
}

std::vector<int> Partition::visibility_order(const vec3d& eye, const vec3d& dir, bool ortho) const {
  std::vector<int> order;
  order.reserve(regions.size());
  visit_front_to_back(*this, 0, eye, dir, ortho, order);
  return order;
}

namespace {
// The longest step the integrator takes in an ABR (grid units) and how far its gradient
// stencil reaches.
double step_length(const Abr& a, const IntegratorSettings& settings) {
  return (settings.adaptive ? double(a.finest_width) : 1.0) / double(settings.rate);
}
double reach(const Abr& a, const IntegratorSettings& settings) {
  return step_length(a, settings) + 0.5 * double(a.finest_width);
}
Box3<double> grown(const Box3<double>& b, double margin) { return {b.lower - vec3d(margin), b.upper + vec3d(margin)}; }
}  // namespace

RankShare rank_share(const AmrTopology& topology, const Box3<double>& region, const IntegratorSettings& settings) {
  RankShare share;
  for (const Abr& a : topology.abrs)
    if (reaches(a.box, region)) share.margin = std::max(share.margin, reach(a, settings));
  std::vector<uint8_t> used(topology.bricks.size(), 0);
  for (uint32_t i = 0; i < topology.abrs.size(); ++i) {
    const Abr& a = topology.abrs[i];
    const double margin = 1.05 * std::max(share.margin, step_length(a, settings)) + 1e-3;
    if (!reaches(a.box, grown(region, margin))) continue;
    share.abrs.push_back(i);
    for (uint32_t k = 0; k < a.brick_count; ++k) used[topology.abr_bricks[a.first_brick + k]] = 1;
  }
  for (uint32_t i = 0; i < used.size(); ++i)
    if (used[i]) share.bricks.push_back(i);
  return share;
}

}  // namespace vs
