#include "volstream/accel/bvh_sah.h"

#include <tbb/task_group.h>

#include <algorithm>
#include <numeric>

namespace vs {
namespace {

constexpr int kBins = 16;
constexpr uint32_t kParallelThreshold = 1 << 13;

float half_area(const box3f& b) {
  if (b.empty()) return 0.f;
  const vec3f s = b.size();
  return s.x * s.y + s.y * s.z + s.z * s.x;
}

int ceil_log2(uint32_t n) {
  int k = 0;
  while ((uint64_t(1) << k) < n) ++k;
  return k;
}

// A subtree over k items takes exactly 2k-1 nodes, so the node range
// of every subtree is known before it is built; subtrees build in parallel, deterministically.
struct SahBuilder {
  const std::vector<box3f>& boxes;
  std::vector<vec3f> centroids;
  std::vector<uint32_t> items;
  std::vector<BvhNode> nodes;

  void build(uint32_t node, uint32_t begin, uint32_t end, uint32_t free, int depth, tbb::task_group& tasks) {
    box3f bounds = box3f::make_empty(), cbounds = box3f::make_empty();
    for (uint32_t i = begin; i < end; ++i) {
      bounds.extend(boxes[items[i]]);
      cbounds.extend(centroids[items[i]]);
    }
    nodes[node].box = bounds;
    if (end - begin == 1) {
      nodes[node].index = items[begin];
      nodes[node].is_leaf = 1;
      return;
    }
    uint32_t mid = 0;
    const bool room = depth + ceil_log2(end - begin) < kMaxBvhDepth - 2;
    if (!(room && sah_split(begin, end, cbounds, mid))) mid = median_split(begin, end, cbounds);
    nodes[node].index = free;
    nodes[node].is_leaf = 0;
    const uint32_t left_free = free + 2, right_free = left_free + 2 * (mid - begin) - 2;
    if (end - begin > kParallelThreshold) {
      tasks.run([=, this, &tasks] { build(free, begin, mid, left_free, depth + 1, tasks); });
    } else {
      build(free, begin, mid, left_free, depth + 1, tasks);
    }
    build(free + 1, mid, end, right_free, depth + 1, tasks);
  }

  // Best of kBins-1 planes per axis by the surface area heuristic; false if none separates.
  bool sah_split(uint32_t begin, uint32_t end, const box3f& cb, uint32_t& mid) {
    float best_cost = INFINITY;
    int best_axis = -1, best_plane = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const float extent = cb.upper[axis] - cb.lower[axis];
      if (!(extent > 0.f)) continue;
      const float scale = float(kBins) / extent;
      box3f bin_box[kBins];
      uint32_t bin_count[kBins] = {};
      for (auto& b : bin_box) b = box3f::make_empty();
      for (uint32_t i = begin; i < end; ++i) {
        const int b = std::min(kBins - 1, int((centroids[items[i]][axis] - cb.lower[axis]) * scale));
        ++bin_count[b];
        bin_box[b].extend(boxes[items[i]]);
      }
      float left_area[kBins - 1];
      uint32_t left_count[kBins - 1];
      box3f acc = box3f::make_empty();
      uint32_t count = 0;
      for (int p = 0; p < kBins - 1; ++p) {
        acc.extend(bin_box[p]);
        count += bin_count[p];
        left_area[p] = half_area(acc);
        left_count[p] = count;
      }
      acc = box3f::make_empty();
      count = 0;
      for (int p = kBins - 2; p >= 0; --p) {
        acc.extend(bin_box[p + 1]);
        count += bin_count[p + 1];
        if (left_count[p] == 0 || count == 0) continue;
        const float cost = left_area[p] * float(left_count[p]) + half_area(acc) * float(count);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_plane = p;
        }
      }
    }
    if (best_axis < 0) return false;
    const float lower = cb.lower[best_axis], scale = float(kBins) / (cb.upper[best_axis] - lower);
    const auto it = std::partition(items.begin() + begin, items.begin() + end, [&](uint32_t item) {
      return std::min(kBins - 1, int((centroids[item][best_axis] - lower) * scale)) <= best_plane;
    });
    mid = uint32_t(it - items.begin());
    return mid > begin && mid < end;
  }

  // Median of the centroids along their longest axis (ties by item index: deterministic).
  uint32_t median_split(uint32_t begin, uint32_t end, const box3f& cb) {
    const vec3f extent = cb.size();
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end, [&](uint32_t a, uint32_t b) {
      const float ca = centroids[a][axis], cb_ = centroids[b][axis];
      return ca < cb_ || (ca == cb_ && a < b);
    });
    return mid;
  }
};

}  // namespace

Bvh build_bvh_sah(const std::vector<box3f>& boxes) {
  Bvh bvh;
  if (boxes.empty()) return bvh;
  SahBuilder b{boxes, {}, std::vector<uint32_t>(boxes.size()), std::vector<BvhNode>(2 * boxes.size() - 1)};
  b.centroids.reserve(boxes.size());
  for (const box3f& box : boxes) b.centroids.push_back(box.center());
  std::iota(b.items.begin(), b.items.end(), 0u);
  tbb::task_group tasks;
  b.build(0, 0, uint32_t(boxes.size()), 1, 0, tasks);
  tasks.wait();
  bvh.nodes = std::move(b.nodes);
  return bvh;
}

}  // namespace vs
