#include "volstream/accel/bvh_wide.h"

#include <cmath>

#include "volstream/backend/parallel.h"

namespace vs {
namespace {

float half_area(const box3f& b) {
  const vec3f d = b.upper - b.lower;
  return d.x > 0.f && d.y > 0.f && d.z > 0.f ? d.x * d.y + d.y * d.z + d.z * d.x : 0.f;
}

// Up to four binary nodes that become the lanes of one wide node, in left-to-right order.
struct Lanes {
  uint32_t node[4];
  int count = 0;
};

class Collapser {
 public:
  explicit Collapser(const std::vector<BvhNode>& binary) : binary_(binary) {}

  Bvh4 run() {
    if (binary_.empty()) return {};
    wide_.nodes.reserve(binary_.size() / 3 + 1);
    wide_.source.reserve(4 * (binary_.size() / 3 + 1));
    // A lone leaf (one region) still gets a wide root, with the leaf in lane 0.
    emit(binary_[0].is_leaf ? Lanes{{0}, 1} : children(0));
    return std::move(wide_);
  }

 private:
  Lanes children(uint32_t inner) const { return {{binary_[inner].index, binary_[inner].index + 1}, 2}; }

  // Opens inner candidates (largest box first) until there are four or only leaves.
  Lanes open(Lanes l) const {
    while (l.count < 4) {
      int best = -1;
      for (int i = 0; i < l.count; ++i)
        if (!binary_[l.node[i]].is_leaf &&
            (best < 0 || half_area(binary_[l.node[i]].box) > half_area(binary_[l.node[best]].box)))
          best = i;
      if (best < 0) break;
      const uint32_t first = binary_[l.node[best]].index;
      for (int i = l.count; i > best + 1; --i) l.node[i] = l.node[i - 1];  // keep the order
      l.node[best] = first;
      l.node[best + 1] = first + 1;
      ++l.count;
    }
    return l;
  }

  // Emits the wide node over `start` (opened) and its subtrees; returns its index.
  uint32_t emit(const Lanes& start) {
    const Lanes l = open(start);
    const uint32_t index = uint32_t(wide_.nodes.size());
    wide_.nodes.emplace_back();
    wide_.source.insert(wide_.source.end(), 4, kBvh4None);
    for (int lane = 0; lane < 4; ++lane) {
      uint32_t child = kBvh4None;
      if (lane < l.count) {
        const BvhNode& b = binary_[l.node[lane]];
        wide_.source[4 * size_t(index) + size_t(lane)] = l.node[lane];
        child = b.is_leaf ? (kBvh4Leaf | b.index) : emit(children(l.node[lane]));
      }
      wide_.nodes[index].child[lane] = child;  // after emit: the vector may have grown
    }
    return index;
  }

  const std::vector<BvhNode>& binary_;
  Bvh4 wide_;
};

}  // namespace

Bvh4 collapse_to_bvh4(const std::vector<BvhNode>& binary) {
  Bvh4 wide = Collapser(binary).run();
  refit_bvh4(wide, binary);
  return wide;
}

void refit_bvh4(Bvh4& wide, const std::vector<BvhNode>& binary) {
  const box3f empty = box3f::make_empty();
  parallel_for("refit_bvh4", int64_t(wide.nodes.size()), [&](int64_t i) {
    Bvh4Node& n = wide.nodes[size_t(i)];
    for (int lane = 0; lane < 4; ++lane) {
      const uint32_t s = wide.source[4 * size_t(i) + size_t(lane)];
      const box3f& b = s == kBvh4None ? empty : binary[s].box;
      for (int a = 0; a < 3; ++a) {
        n.lower[a][lane] = b.lower[a];
        n.upper[a][lane] = b.upper[a];
      }
    }
  });
}

}  // namespace vs
