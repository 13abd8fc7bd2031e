#include "volstream/accel/bvh_sah.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <cstring>

#include "volstream/core/simd.h"

namespace vs {
namespace {

constexpr int kBins = 16;
constexpr uint32_t kParallelThreshold = 1 << 13;
constexpr uint32_t kParallelBinning = 1 << 15;  // ranges this large bin their items in parallel

int ceil_log2(uint32_t n) {
  int k = 0;
  while ((uint64_t(1) << k) < n) ++k;
  return k;
}

using simd::f4, simd::i4;  // x, y, z and one unused lane

inline f4 vmin4(f4 a, f4 b) { return a < b ? a : b; }
inline f4 vmax4(f4 a, f4 b) { return a > b ? a : b; }
inline box3f to_box(f4 lo, f4 hi) { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }

// One item, stored by value so that the passes over a range read memory in order (the items
// are partitioned in place, as an index array would be: the same permutation, the same tree).
// Lane 3 of lo holds the item index (its bits); lanes 3 of hi and c are 0.
struct Prim {
  f4 lo, hi, c;  // box and its centre (box3f::center, computed once)
  uint32_t id() const {
    const float bits = lo[3];  // Clang takes no address of a vector lane: copy the lane out
    uint32_t v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
};

// Bounds of a range of items and of their centroids (lane 3: min/max only, never read).
struct Bounds {
  f4 lo = f4{} + INFINITY, hi = f4{} - INFINITY, clo = f4{} + INFINITY, chi = f4{} - INFINITY;
  void add(const Prim& p) {
    lo = vmin4(lo, p.lo);
    hi = vmax4(hi, p.hi);
    clo = vmin4(clo, p.c);
    chi = vmax4(chi, p.c);
  }
  void add(const Bounds& b) {
    lo = vmin4(lo, b.lo);
    hi = vmax4(hi, b.hi);
    clo = vmin4(clo, b.clo);
    chi = vmax4(chi, b.chi);
  }
  box3f box() const { return to_box(lo, hi); }
  box3f cbox() const { return to_box(clo, chi); }
};

// The bins of all three axes, filled in one pass. A bin's box is written by its first item
// (count 0 -> 1) and read only when its count is not 0, so a node clears the counts only.
// Counts add and boxes take min/max: any grouping of the items (parallel reduction) gives the
// same bins.
struct Bins {
  struct Box {
    f4 lo, hi, clo, chi;  // items' boxes and centroids
  };
  uint32_t count[3][kBins] = {};
  Box bin[3][kBins];
  void add(int axis, int b, const Prim& p) {
    Box& x = bin[axis][b];
    if (count[axis][b]++ == 0) {
      x = {p.lo, p.hi, p.c, p.c};
    } else {
      x = {vmin4(x.lo, p.lo), vmax4(x.hi, p.hi), vmin4(x.clo, p.c), vmax4(x.chi, p.c)};
    }
  }
  void add(const Bins& o) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < kBins; ++b) {
        if (o.count[a][b] == 0) continue;
        Box& x = bin[a][b];
        const Box& y = o.bin[a][b];
        x = count[a][b] == 0 ? y : Box{vmin4(x.lo, y.lo), vmax4(x.hi, y.hi), vmin4(x.clo, y.clo), vmax4(x.chi, y.chi)};
        count[a][b] += o.count[a][b];
      }
  }
};

// half_area of the box [lo, hi] (lanes 0-2), the same floats as half_area(box3f).
float half_area4(f4 lo, f4 hi) {
  if (lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2]) return 0.f;
  const f4 s = hi - lo;
  return s[0] * s[1] + s[1] * s[2] + s[2] * s[0];
}

// A subtree over k items takes exactly 2k-1 nodes, so the node range
// of every subtree is known before it is built; subtrees build in parallel, deterministically.
struct SahBuilder {
  std::vector<Prim> prims;
  std::vector<BvhNode> nodes;

  Bounds bounds_of(uint32_t begin, uint32_t end) const {
    Bounds b;
    for (uint32_t i = begin; i < end; ++i) b.add(prims[i]);
    return b;
  }

  // bounds: those of the items [begin, end) when the parent's bins gave them, else null.
  void build(uint32_t node, uint32_t begin, uint32_t end, uint32_t free, int depth, const Bounds* known,
             tbb::task_group& tasks) {
    const Bounds bounds = known ? *known : bounds_of(begin, end);
    nodes[node].box = bounds.box();
    if (end - begin == 1) {
      nodes[node].index = prims[begin].id();
      nodes[node].is_leaf = 1;
      return;
    }
    uint32_t mid = 0;
    Bounds left, right;
    bool children_known = false;
    const bool room = depth + ceil_log2(end - begin) < kMaxBvhDepth - 2;
    if (room && end - begin == 2 && split_pair(begin, bounds.cbox())) {
      const Prim &a = prims[begin], &b = prims[begin + 1];
      nodes[node].index = free;
      nodes[node].is_leaf = 0;
      nodes[free] = {to_box(a.lo, a.hi), a.id(), 1};
      nodes[free + 1] = {to_box(b.lo, b.hi), b.id(), 1};
      return;
    }
    if (room && sah_split(begin, end, bounds.cbox(), mid, left, right)) {
      children_known = true;
    } else {
      mid = median_split(begin, end, bounds.cbox());
    }
    nodes[node].index = free;
    nodes[node].is_leaf = 0;
    const uint32_t left_free = free + 2, right_free = left_free + 2 * (mid - begin) - 2;
    if (end - begin > kParallelThreshold) {
      tasks.run([=, this, &tasks] {  // left by value: this frame may be gone when the task runs
        build(free, begin, mid, left_free, depth + 1, children_known ? &left : nullptr, tasks);
      });
    } else {
      build(free, begin, mid, left_free, depth + 1, children_known ? &left : nullptr, tasks);
    }
    build(free + 1, mid, end, right_free, depth + 1, children_known ? &right : nullptr, tasks);
  }

  void bin_range(uint32_t begin, uint32_t end, f4 lower, f4 scale, Bins& bins) const {
    const i4 last = i4{} + (kBins - 1);
    for (uint32_t i = begin; i < end; ++i) {
      const Prim& p = prims[i];
      // The bin on each axis, as the scalar int((c - lower) * scale) (unused axes: scale 0).
      i4 b = __builtin_convertvector((p.c - lower) * scale, i4);
      b = b < last ? b : last;
      for (int axis = 0; axis < 3; ++axis) bins.add(axis, b[axis], p);
    }
  }

  // Two items, the most common node: what sah_split decides, without bins. Each axis on which
  // the centroids differ puts them in bins 0 and kBins-1 and offers one split, the same on every
  // such axis (the same two boxes); the first axis and its highest plane win, so the item with
  // the lower centroid on the first such axis goes left. False (nothing reordered) when sah_split
  // would not split (equal centroids, or a cost that is not finite): the caller then runs the
  // general path.
  bool split_pair(uint32_t begin, const box3f& cb) {
    int axis = 0;
    while (axis < 3 && !(cb.upper[axis] - cb.lower[axis] > 0.f)) ++axis;
    if (axis == 3) return false;
    Prim &a = prims[begin], &b = prims[begin + 1];
    const bool swap = b.c[axis] < a.c[axis];
    const Prim& l = swap ? b : a;
    const Prim& r = swap ? a : b;
    const float cost = half_area4(l.lo, l.hi) * 1.f + half_area4(r.lo, r.hi) * 1.f;
    if (!(cost < INFINITY)) return false;
    if (swap) std::swap(a, b);
    return true;
  }

  // Best of kBins-1 planes per axis by the surface area heuristic; false if none separates.
  // On success, left and right are the bounds of the two sides.
  bool sah_split(uint32_t begin, uint32_t end, const box3f& cb, uint32_t& mid, Bounds& left, Bounds& right) {
    f4 scale = {0.f, 0.f, 0.f, 0.f};
    const f4 lower = {cb.lower.x, cb.lower.y, cb.lower.z, 0.f};
    bool use[3] = {false, false, false};
    for (int axis = 0; axis < 3; ++axis) {
      const float extent = cb.upper[axis] - cb.lower[axis];
      use[axis] = extent > 0.f;
      if (use[axis]) scale[axis] = float(kBins) / extent;
    }
    Bins bins;
    if (end - begin >= kParallelBinning) {
      bins = tbb::parallel_reduce(
          tbb::blocked_range<uint32_t>(begin, end, 4096), Bins{},
          [&](const tbb::blocked_range<uint32_t>& r, Bins acc) {
            bin_range(r.begin(), r.end(), lower, scale, acc);
            return acc;
          },
          [](Bins a, const Bins& b) {
            a.add(b);
            return a;
          });
    } else {
      bin_range(begin, end, lower, scale, bins);
    }
    float best_cost = INFINITY;
    int best_axis = -1, best_plane = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (!use[axis]) continue;
      const Bins::Box* bin = bins.bin[axis];
      const uint32_t* n = bins.count[axis];
      float left_area[kBins - 1];
      uint32_t left_count[kBins - 1];
      f4 lo = f4{} + INFINITY, hi = f4{} - INFINITY;
      uint32_t count = 0;
      for (int p = 0; p < kBins - 1; ++p) {
        if (n[p] != 0) {
          lo = vmin4(lo, bin[p].lo);
          hi = vmax4(hi, bin[p].hi);
          count += n[p];
        }
        left_area[p] = half_area4(lo, hi);
        left_count[p] = count;
      }
      lo = f4{} + INFINITY;
      hi = f4{} - INFINITY;
      count = 0;
      // Planes high to low, strict improvement: among planes that split alike (empty bins
      // between them) the highest wins, so a plane whose upper bin is empty is skipped.
      for (int p = kBins - 2; p >= 0; --p) {
        if (n[p + 1] == 0) continue;
        lo = vmin4(lo, bin[p + 1].lo);
        hi = vmax4(hi, bin[p + 1].hi);
        count += n[p + 1];
        if (left_count[p] == 0) continue;
        const float cost = left_area[p] * float(left_count[p]) + half_area4(lo, hi) * float(count);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_plane = p;
        }
      }
    }
    if (best_axis < 0) return false;
    const float lo = cb.lower[best_axis], s = scale[best_axis];
    const auto it = std::partition(prims.begin() + begin, prims.begin() + end, [&](const Prim& p) {
      return std::min(kBins - 1, int((p.c[best_axis] - lo) * s)) <= best_plane;
    });
    mid = uint32_t(it - prims.begin());
    if (!(mid > begin && mid < end)) return false;
    left = right = Bounds{};
    for (int p = 0; p < kBins; ++p) {
      if (bins.count[best_axis][p] == 0) continue;
      const Bins::Box& x = bins.bin[best_axis][p];
      Bounds& side = p <= best_plane ? left : right;
      side.lo = vmin4(side.lo, x.lo);
      side.hi = vmax4(side.hi, x.hi);
      side.clo = vmin4(side.clo, x.clo);
      side.chi = vmax4(side.chi, x.chi);
    }
    return true;
  }

  // Median of the centroids along their longest axis (ties by item index: deterministic).
  uint32_t median_split(uint32_t begin, uint32_t end, const box3f& cb) {
    const vec3f extent = cb.size();
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(prims.begin() + begin, prims.begin() + mid, prims.begin() + end,
                     [&](const Prim& a, const Prim& b) {
                       const float ca = a.c[axis], cb_ = b.c[axis];
                       return ca < cb_ || (ca == cb_ && a.id() < b.id());
                     });
    return mid;
  }
};

}  // namespace

Bvh build_bvh_sah(const std::vector<box3f>& boxes) {
  Bvh bvh;
  if (boxes.empty()) return bvh;
  SahBuilder b{std::vector<Prim>(boxes.size()), std::vector<BvhNode>(2 * boxes.size() - 1)};
  for (size_t i = 0; i < boxes.size(); ++i) {
    const box3f& x = boxes[i];
    const vec3f c = x.center();
    const uint32_t id = uint32_t(i);
    float id_bits;
    std::memcpy(&id_bits, &id, sizeof id);
    Prim& p = b.prims[i];
    p.lo = f4{x.lower.x, x.lower.y, x.lower.z, id_bits};
    p.hi = simd::lanes_of(x.upper);
    p.c = simd::lanes_of(c);
  }
  tbb::task_group tasks;
  b.build(0, 0, uint32_t(boxes.size()), 1, 0, nullptr, tasks);
  tasks.wait();
  bvh.nodes = std::move(b.nodes);
  return bvh;
}

}  // namespace vs
