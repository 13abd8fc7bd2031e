// Paper 002's compact encoding of an unstructured mesh (issue 13), first slice, built from the
// reference encoding (umesh.h) and sampled through the same integrator (MeshVolume<CompactMeshView>):
//   - elements in a spatial (Morton) order, cut into multi-leaves of at most kMultiLeafSize
//     elements, grouped by type inside a leaf, each element only the indices its type needs;
//   - sub-meshes of consecutive leaves with at most 65536 vertices, so indices are 16-bit local
//     ones; the vertices a sub-mesh shares with another are replicated (counted: `replicated`);
//   - an 8-wide BVH over the leaves, built bottom-up over the Morton order, whose child boxes are
//     quantized to 8 bits per coordinate relative to the node's box (rounded outwards, so they
//     always hold their children), with children addressed implicitly (first + i: no pointers,
//     no item list);
//   - field values per local vertex (replicated like the vertices).
// Sampling decodes a leaf on the fly; the ray's hint is the element (leaf and slot) of its last
// sample: that element, its leaf from there out, the leaves beside it, then the BVH.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/core/math.h"
#include "volstream/umesh/shape.h"
#include "volstream/umesh/umesh.h"

namespace vs {

inline constexpr int kCompactWidth = 8;
inline constexpr uint32_t kMultiLeafSize = 32;

struct CompactNode {
  vec3f origin, scale;              // child box corner = origin + q * scale, q in 0..255
  uint8_t lower[kCompactWidth][3];  // quantized child boxes, rounded outwards
  uint8_t upper[kCompactWidth][3];
  uint32_t first;         // first child: a node, or a leaf when leaf_children
  uint8_t count;          // children, 1..8
  uint8_t leaf_children;  // 1: the children are leaves
  uint8_t pad[2];
  VS_HOST_DEVICE box3f child_box(int i) const {
    return {origin + vec3f(float(lower[i][0]), float(lower[i][1]), float(lower[i][2])) * scale,
            origin + vec3f(float(upper[i][0]), float(upper[i][1]), float(upper[i][2])) * scale};
  }
};
static_assert(sizeof(CompactNode) == 80);

struct CompactLeaf {
  uint32_t submesh;
  uint32_t first_index;  // into the 16-bit index stream
  uint8_t counts[4];     // elements per type, type_slot order (tetra, pyramid, wedge, hexahedron)
};
static_assert(sizeof(CompactLeaf) == 12);

struct CompactSubmesh {
  uint32_t first_vertex;  // into the local vertex array (and every field's values)
};

// The bytes of each part (bytes_per_element's breakdown).
struct CompactBytes {
  uint64_t vertices = 0, indices = 0, leaves = 0, nodes = 0, submeshes = 0, field = 0;
  uint64_t total() const { return vertices + indices + leaves + nodes + submeshes + field; }
};

struct CompactMesh {
  std::vector<CompactNode> nodes;  // nodes[0] is the root
  std::vector<CompactLeaf> leaves;
  std::vector<uint16_t> indices;
  std::vector<CompactSubmesh> submeshes;
  std::vector<vec3f> vertices;            // local vertices, sub-mesh after sub-mesh
  std::vector<uint32_t> source_vertex;    // local vertex -> the reference vertex (gathers fields)
  uint64_t elements = 0, replicated = 0;  // local vertices beyond the mesh's own
  uint32_t leaf_parents = 0;              // index of the first node whose children are leaves
  CompactBytes bytes() const;
  // A field given per reference vertex, per local vertex (what the renderer samples).
  std::vector<float> gather(const float* reference_values) const;
};

CompactMesh build_compact_mesh(const UMesh& mesh);

// Everything sampling reads (host or device pointers).
struct CompactMeshView {
  const CompactNode* nodes = nullptr;
  const CompactLeaf* leaves = nullptr;
  const uint16_t* indices = nullptr;
  const CompactSubmesh* submeshes = nullptr;
  const vec3f* vertices = nullptr;
  uint32_t leaf_count = 0;
  uint32_t leaf_parents = 0;  // the first node whose children are leaves (leaf l: its child l % 8)
  static constexpr uint32_t kNeighbourLeaves = 2;

  VS_HOST_DEVICE box3f leaf_box(uint32_t l) const {
    return nodes[leaf_parents + l / kCompactWidth].child_box(int(l % kCompactWidth));
  }

  struct Hit {
    int64_t leaf = -1;
    uint32_t slot = 0;  // the element within the leaf
    uint32_t first_vertex = 0;
    uint16_t v[8];
    int n = 0;
    float w[8];
  };

  // Element k of leaf `leaf` (types in type_slot order): its vertex count and first index.
  VS_HOST_DEVICE const uint16_t* element(const CompactLeaf& leaf, uint32_t k, int& n) const {
    constexpr int kVertices[4] = {4, 5, 6, 8};
    const uint16_t* index = indices + leaf.first_index;
    for (int type = 0; type < 4; ++type) {
      if (k < leaf.counts[type]) {
        n = kVertices[type];
        return index + k * uint32_t(n);
      }
      k -= leaf.counts[type];
      index += uint32_t(leaf.counts[type]) * uint32_t(kVertices[type]);
    }
    n = 0;
    return index;
  }

  // Tests element k of leaf l (hit and best as for UMeshView::consider: a strict hit wins, else
  // the nearest within the tolerance); true on a strict hit.
  VS_HOST_DEVICE bool test_element(uint32_t l, uint32_t k, const vec3f& p, Hit& hit, float& best) const {
    const CompactLeaf& leaf = leaves[l];
    int n;
    const uint16_t* index = element(leaf, k, n);
    const uint32_t base = submeshes[leaf.submesh].first_vertex;
    vec3f x[8];
    box3f b = box3f::make_empty();
    for (int i = 0; i < n; ++i) {
      x[i] = vertices[base + index[i]];
      b.extend(x[i]);
    }
    float w[8], outside;
    if (!b.contains(p) || !shape::locate_in_element(n, x, p, w, &outside) || !(outside < best)) return false;
    best = outside;
    hit.leaf = l;
    hit.slot = k;
    hit.first_vertex = base;
    hit.n = n;
    for (int i = 0; i < n; ++i) hit.v[i] = index[i], hit.w[i] = w[i];
    return outside <= 0.f;
  }

  // Tests the elements of leaf l, nearest to element `start` first (elements are in Morton
  // order: the previous sample's neighbours are close by); true on a strict hit.
  VS_HOST_DEVICE bool test_leaf(uint32_t l, const vec3f& p, Hit& hit, float& best, uint32_t start = 0) const {
    const CompactLeaf& leaf = leaves[l];
    const uint32_t count = uint32_t(leaf.counts[0]) + leaf.counts[1] + leaf.counts[2] + leaf.counts[3];
    if (start >= count) start = 0;
    for (uint32_t d = 0; d < count; ++d) {
      if (start + d < count && test_element(l, start + d, p, hit, best)) return true;
      if (d > 0 && d <= start && test_element(l, start - d, p, hit, best)) return true;
      if (start + d >= count && d > start) break;
    }
    return false;
  }

  VS_HOST_DEVICE bool search(const vec3f& p, Hit& hit, float& best) const {
    uint32_t stack[64];
    int top = 0;
    if (!nodes) return false;
    stack[top++] = 0;
    while (top > 0) {
      const CompactNode& node = nodes[stack[--top]];
      for (int i = node.count - 1; i >= 0; --i) {
        if (!node.child_box(i).contains(p)) continue;
        if (node.leaf_children) {
          if (test_leaf(node.first + uint32_t(i), p, hit, best)) return true;
        } else if (top < 64) {
          stack[top++] = node.first + uint32_t(i);
        }
      }
    }
    return false;
  }

  // The element holding p, trying the ray's previous element first, then its leaf from there
  // out (hint = leaf * kMultiLeafSize + slot); the element found is the next hint.
  VS_HOST_DEVICE Hit locate(const vec3f& p, int64_t& hint) const {
    Hit hit;
    float best = INFINITY;
    bool strict = false;
    if (hint >= 0) {
      const uint32_t leaf = uint32_t(hint / kMultiLeafSize);
      strict = test_leaf(leaf, p, hit, best, uint32_t(hint % kMultiLeafSize));
      // Then the leaves beside it in the Morton order, whose boxes hold p.
      for (uint32_t d = 1; d <= kNeighbourLeaves && !strict; ++d) {
        if (leaf >= d && leaf_box(leaf - d).contains(p)) strict = test_leaf(leaf - d, p, hit, best);
        if (!strict && leaf + d < leaf_count && leaf_box(leaf + d).contains(p))
          strict = test_leaf(leaf + d, p, hit, best);
      }
    }
    if (!strict) search(p, hit, best);
    if (hit.leaf >= 0) hint = hit.leaf * int64_t(kMultiLeafSize) + hit.slot;
    return hit;
  }

  VS_HOST_DEVICE float sample(const float* values, const vec3f& p, int64_t& hint) const {
    const Hit hit = locate(p, hint);
    if (hit.leaf < 0) return NAN;
    float f = 0.f;
    for (int i = 0; i < hit.n; ++i) f += hit.w[i] * values[hit.first_vertex + hit.v[i]];
    return f;
  }
  VS_HOST_DEVICE float sample(const float* values, const vec3f& p) const {
    int64_t no_hint = -1;
    return sample(values, p, no_hint);
  }
};

}  // namespace vs
