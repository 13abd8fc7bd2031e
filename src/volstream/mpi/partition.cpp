#include "volstream/mpi/partition.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

// The kd recursion over any cost model: each node cuts the longest side of the data inside its
// region at the candidate plane that gives the left side its ranks' share of the cost.
struct Builder {
  const SplitCost& model;
  Box3<double> data;  // bounds of the data (model.data_bounds())
  Partition out;

  double split_plane(const Box3<double>& region, int axis, double share) const {
    const std::vector<double> planes = model.planes(region, axis);
    if (planes.empty()) return std::max(region.lower[axis], data.lower[axis]);
    const double total = model.cost(region);
    auto left_cost = [&](size_t k) {
      Box3<double> left = region;
      left.upper[axis] = planes[k];
      return model.cost(left);
    };
    size_t a = 0, b = planes.size() - 1;
    while (a < b) {  // the first plane with at least `share` on its left
      const size_t m = a + (b - a) / 2;
      if (left_cost(m) < share * total)
        a = m + 1;
      else
        b = m;
    }
    // The one before may be closer to the share.
    if (a > 0 && std::fabs(left_cost(a - 1) - share * total) < std::fabs(left_cost(a) - share * total)) --a;
    return planes[a];
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

// AMR: cells weighted by render cost, cut on the coarsest cells' faces.
class BrickCost : public SplitCost {
 public:
  explicit BrickCost(const std::vector<Brick>& bricks) : bricks_(bricks) {
    for (const Brick& br : bricks) {
      max_level_ = std::max(max_level_, br.level);
      const box3i c = br.cell_box();
      data_.extend(Box3<double>{vec3d(c.lower), vec3d(c.upper)});
    }
  }
  Box3<double> data_bounds() const override { return data_; }
  double cost(const Box3<double>& region) const override {
    double c = 0;
    for (const Brick& b : bricks_) c += double(cells_in(b, region)) * cell_cost(b.level, max_level_);
    return c;
  }
  std::vector<double> planes(const Box3<double>& region, int axis) const override {
    const double w = double(level_width(max_level_));
    const double lo = std::max(region.lower[axis], data_.lower[axis]);
    const double hi = std::min(region.upper[axis], data_.upper[axis]);
    std::vector<double> out;
    for (int64_t k = int64_t(std::ceil(lo / w)), last = int64_t(std::floor(hi / w)); k <= last; ++k)
      out.push_back(double(k) * w);
    return out;
  }

 private:
  const std::vector<Brick>& bricks_;
  int32_t max_level_ = 0;
  Box3<double> data_ = Box3<double>::make_empty();
};

// Meshes: one unit per element, at its centroid (or a compact leaf's elements at its point); cut
// halfway between neighbouring points, so that no point lies on a plane.
class PointCost : public SplitCost {
 public:
  PointCost(const std::vector<vec3d>& points, const std::vector<uint32_t>& weights)
      : points_(points), weights_(weights) {
    if (!weights.empty() && weights.size() != points.size()) throw std::logic_error("a weight per point");
    for (const vec3d& p : points) data_.extend(p);
  }
  Box3<double> data_bounds() const override { return data_; }
  double cost(const Box3<double>& region) const override {
    uint64_t n = 0;
    for (size_t i = 0; i < points_.size(); ++i)
      if (in_region(region, points_[i])) n += weights_.empty() ? 1 : weights_[i];
    return double(n);
  }
  std::vector<double> planes(const Box3<double>& region, int axis) const override {
    std::vector<double> at;
    for (const vec3d& p : points_)
      if (in_region(region, p)) at.push_back(p[axis]);
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end()), at.end());
    std::vector<double> out;
    for (size_t i = 1; i < at.size(); ++i) out.push_back(0.5 * (at[i - 1] + at[i]));
    return out;
  }

 private:
  const std::vector<vec3d>& points_;
  const std::vector<uint32_t>& weights_;  // empty: one each
  Box3<double> data_ = Box3<double>::make_empty();
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

Partition partition_by_cost(const SplitCost& model, int ranks) {
  if (ranks < 1) throw UsageError("a partition needs at least one rank");
  Builder b{model, model.data_bounds(), {}};
  b.out.regions.resize(size_t(ranks));
  b.build({vec3d(-kInf), vec3d(kInf)}, 0, ranks);
  return std::move(b.out);
}

Partition partition_bricks(const std::vector<Brick>& bricks, int ranks) {
  return partition_by_cost(BrickCost(bricks), ranks);
}

Partition partition_points(const std::vector<vec3d>& points, int ranks, const std::vector<uint32_t>& weights) {
  return partition_by_cost(PointCost(points, weights), ranks);
}

std::vector<int> Partition::visibility_order(const vec3d& eye, const vec3d& dir, bool ortho) const {
  std::vector<int> order;
  order.reserve(regions.size());
  visit_front_to_back(*this, 0, eye, dir, ortho, order);
  return order;
}

namespace {
// The longest step the integrator takes in a region of finest width w (grid units), and how far
// its gradient stencil reaches.
double step_length(float width, const IntegratorSettings& settings) {
  return (settings.adaptive ? double(width) : 1.0) / double(settings.rate);
}
double reach(float width, const IntegratorSettings& settings) {
  return step_length(width, settings) + 0.5 * double(width);
}
Box3<double> grown(const Box3<double>& b, double margin) { return {b.lower - vec3d(margin), b.upper + vec3d(margin)}; }
}  // namespace

bool in_region(const Box3<double>& r, const vec3d& p) {
  return p.x >= r.lower.x && p.x < r.upper.x && p.y >= r.lower.y && p.y < r.upper.y && p.z >= r.lower.z &&
         p.z < r.upper.z;
}

HeldRegions held_regions(const std::vector<RegionExtent>& regions, const Box3<double>& region,
                         const IntegratorSettings& settings) {
  HeldRegions held;
  for (const RegionExtent& r : regions)
    if (reaches(r.box, region)) held.margin = std::max(held.margin, reach(r.width, settings));
  for (uint32_t i = 0; i < regions.size(); ++i) {
    const double margin = 1.05 * std::max(held.margin, step_length(regions[i].width, settings)) + 1e-3;
    if (reaches(regions[i].box, grown(region, margin))) held.indices.push_back(i);
  }
  return held;
}

RankShare rank_share(const AmrTopology& topology, const Box3<double>& region, const IntegratorSettings& settings) {
  std::vector<RegionExtent> extents;
  extents.reserve(topology.abrs.size());
  for (const Abr& a : topology.abrs) extents.push_back({a.box, float(a.finest_width)});
  HeldRegions held = held_regions(extents, region, settings);
  RankShare share;
  share.margin = held.margin;
  share.abrs = std::move(held.indices);
  std::vector<uint8_t> used(topology.bricks.size(), 0);
  for (uint32_t i : share.abrs) {
    const Abr& a = topology.abrs[i];
    for (uint32_t k = 0; k < a.brick_count; ++k) used[topology.abr_bricks[a.first_brick + k]] = 1;
  }
  for (uint32_t i = 0; i < used.size(); ++i)
    if (used[i]) share.bricks.push_back(i);
  return share;
}

}  // namespace vs
