// The reference encoding's acceleration structure for point location: a binary BVH over the
// elements' boxes with up to kElementLeafSize elements per leaf, addressed through an item list
// (the layout of paper 002's baseline: 32 B nodes plus 4 B per element of item list). Built by
// median splits on the longest axis of the centroids (balanced: depth ~ log2(elements / leaf)).
// Children of an inner node are adjacent (first, first + 1).
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/core/math.h"
#include "volstream/umesh/shape.h"
#include "volstream/umesh/umesh.h"

namespace vs {

inline constexpr uint32_t kElementLeafSize = 4;

struct ElementBvhNode {
  box3f box;
  uint32_t first;  // inner: left child (right = first + 1); leaf: first item
  uint32_t count;  // 0: inner node; else the leaf's item count
};

struct ElementBvh {
  std::vector<ElementBvhNode> nodes;  // nodes[0] is the root
  std::vector<uint32_t> items;        // element indices in leaf order
  std::vector<uint32_t> parents;      // per node: its parent (the root's is 0); for searches from a leaf
};

ElementBvh build_element_bvh(const std::vector<box3f>& element_boxes);

// The element containing p and its interpolation weights (w[0..vertex_count)), or -1.
struct ElementHit {
  int64_t element = -1;
  float w[8];
};

// Everything point location reads (host or device pointers).
struct UMeshView {
  const vec3f* vertices = nullptr;
  const UElement* elements = nullptr;
  const ElementBvhNode* nodes = nullptr;
  const uint32_t* items = nullptr;
  uint32_t node_count = 0;
  const uint32_t* parents = nullptr;  // per node (the root's unused); null: searches start at the root

  // Weights of element e at p (false: p is outside it, or outside its corners' box, which the
  // BVH's boxes are made of). `outside` as in shape::locate_in_element.
  VS_HOST_DEVICE bool in_element(uint32_t e, const vec3f& p, float* w, float* outside) const {
    const UElement& el = elements[e];
    const int n = el.vertex_count();
    vec3f x[8];
    box3f b = box3f::make_empty();
    for (int i = 0; i < n; ++i) {
      x[i] = vertices[el.v[i]];
      b.extend(x[i]);
    }
    return b.contains(p) && shape::locate_in_element(n, x, p, w, outside);
  }

  // Tests candidate element e: a strict hit ends the search (true), a hit within the tolerance
  // is kept unless a closer one is known.
  VS_HOST_DEVICE bool consider(uint32_t e, const vec3f& p, ElementHit& hit, float& best) const {
    float w[8], outside;
    if (!in_element(e, p, w, &outside) || !(outside < best)) return false;
    best = outside;
    hit.element = e;
    for (int i = 0; i < 8; ++i) hit.w[i] = w[i];
    return outside <= 0.f;
  }

  // Searches the subtree under node `root` for p (hit and best as in consider): true on a strict
  // hit. `leaf` is set to the leaf of the best hit found.
  VS_HOST_DEVICE bool search(uint32_t root, const vec3f& p, ElementHit& hit, float& best, uint32_t& leaf) const {
    uint32_t stack[64];
    int top = 0;
    stack[top++] = root;
    while (top > 0) {
      const uint32_t index = stack[--top];
      const ElementBvhNode& node = nodes[index];
      if (!node.box.contains(p)) continue;
      if (node.count == 0) {
        stack[top++] = node.first + 1;
        stack[top++] = node.first;
        continue;
      }
      for (uint32_t k = 0; k < node.count; ++k) {
        const int64_t before = hit.element;
        const bool strict = consider(items[node.first + k], p, hit, best);
        if (hit.element != before) leaf = index;
        if (strict) return true;
      }
    }
    return false;
  }

  VS_HOST_DEVICE ElementHit locate(const vec3f& p) const {
    int64_t no_hint = -1;
    return locate(p, no_hint);
  }

  // locate(p) starting at leaf `hint` (the leaf of the ray's previous sample; -1: none), then
  // the sibling subtrees on the way up to the root: consecutive samples are close, so the
  // search usually ends a few levels up instead of descending from the root. It is exhaustive
  // all the same (a strict hit wins wherever it is). The leaf found is the next hint.
  VS_HOST_DEVICE ElementHit locate(const vec3f& p, int64_t& hint) const {
    ElementHit hit;
    float best = INFINITY;
    uint32_t leaf = 0;
    if (node_count == 0) return hit;
    uint32_t node = hint >= 0 && parents ? uint32_t(hint) : 0u;
    bool strict = search(node, p, hit, best, leaf);
    while (!strict && node != 0) {
      const uint32_t parent = parents[node];
      const uint32_t sibling = nodes[parent].first == node ? node + 1 : node - 1;
      strict = search(sibling, p, hit, best, leaf);
      node = parent;
    }
    if (hit.element >= 0) hint = leaf;
    return hit;
  }

  // The field's value at p, NaN outside every element.
  VS_HOST_DEVICE float sample(const float* values, const vec3f& p) const {
    int64_t no_hint = -1;
    return sample(values, p, no_hint);
  }
  VS_HOST_DEVICE float sample(const float* values, const vec3f& p, int64_t& hint) const {
    const ElementHit hit = locate(p, hint);
    if (hit.element < 0) return NAN;
    const UElement& el = elements[hit.element];
    const int n = el.vertex_count();
    float f = 0.f;
    for (int i = 0; i < n; ++i) f += hit.w[i] * values[el.v[i]];
    return f;
  }
};

}  // namespace vs
