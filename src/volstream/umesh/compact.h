// Paper 002's compact encoding of an unstructured mesh (issue 13), built from the reference
// encoding (umesh.h) and sampled through the same integrator (MeshVolume<CompactMeshView>):
//   - elements cut into multi-leaves of at most kMultiLeafSize by median splits (compact
//     clusters; half as many where a leaf holds other elements than tets), each element only
//     the corners its type needs;
//   - sub-meshes of consecutive leaves with at most 65536 vertices, so vertex indices are 16-bit
//     local ones; the vertices a sub-mesh shares with another are replicated (`replicated`);
//   - per leaf a table of its distinct vertices (16-bit sub-mesh indices), and each corner one
//     byte into that table: a cluster's elements share most of their vertices;
//   - tets that share a face grouped in pairs: the face's three corners, then each tet's fourth
//     (5 bytes for two tets instead of 8);
//   - an 8-wide BVH over the leaves, built bottom-up over the leaf order, whose child boxes are
//     quantized to 8 bits per coordinate relative to the node's box (rounded outwards, so they
//     always hold their children), with children addressed implicitly (first + i: no pointers,
//     no item list);
//   - field values per local vertex (replicated like the vertices).
// Sampling decodes a leaf on the fly and walks from the ray's previous element across faces,
// finding the neighbour by comparing vertex indices (no adjacency stored): in its leaf, then the
// leaves whose boxes hold the face, near ones in the tree first (by position in another
// sub-mesh); else a BVH search decides. On the CPU each thread keeps the neighbours it found
// last (NeighbourCache): the rays of a tile cross the same faces.
#pragma once
#include <cfloat>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "volstream/core/math.h"
#include "volstream/umesh/macro_grid.h"
#include "volstream/umesh/shape.h"
#include "volstream/umesh/umesh.h"

namespace vs {

inline constexpr int kCompactWidth = 8;
// Elements per multi-leaf at most: 64 tets (256 corners, so a byte per corner always reaches
// the table), or 32 elements of other types. On a 1M-tet mesh 64 instead of 32 took the all-in
// bytes per element from 8.10 to 7.38 (half the leaf records and tree nodes, tables shared by
// more tets) at about the same sampling speed (bench/RESULTS.md).
inline constexpr uint32_t kMultiLeafSize = 64;

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

// The children of `node` whose boxes may hold the box [lo, hi] (a point: lo = hi), one bit each.
// The box is compared in the node's quantized coordinates (integer compares, no child box
// decoded), widened by more than float rounding can move it, so a child whose box holds it is
// never dropped (one more is a wasted test, not a wrong answer).
VS_HOST_DEVICE inline uint32_t children_holding(const CompactNode& node, const vec3f& lo, const vec3f& hi) {
  int qlo[3], qhi[3];
  for (int a = 0; a < 3; ++a) {
    const float s = node.scale[a], dl = lo[a] - node.origin[a], dh = hi[a] - node.origin[a];
    if (!(s > 0.f)) {  // a flat node: every child box is the plane at the origin
      if (!(dl == 0.f && dh == 0.f)) return 0u;
      qlo[a] = qhi[a] = 0;
      continue;
    }
    // One division per axis (the hot path of every neighbour search): a product by the
    // reciprocal is within a few units of 1e-5 of the quotient, far inside the slack.
    const float inv = 1.f / s;
    const float magnitude = fabsf(lo[a]) > fabsf(hi[a]) ? fabsf(lo[a]) : fabsf(hi[a]);
    const float slack = 1e-3f + (magnitude + fabsf(node.origin[a])) * (4.f * FLT_EPSILON) * inv;
    // floor and ceil by truncating positive numbers (floorf/ceilf and fminf are calls on
    // baseline x86-64; a NaN falls to -1, outside every child).
    const float up = dl * inv + slack, down = dh * inv - slack;
    qlo[a] = int((up > -1.f ? (up < 256.f ? up : 256.f) : -1.f) + 1.f) - 1;
    qhi[a] = 257 - int(257.f - (down > -1.f ? (down < 256.f ? down : 256.f) : -1.f));
    if (qlo[a] < 0 || qhi[a] > 255) return 0u;  // beyond the node's box: no child holds it
  }
  // Every slot compared without branches (unused slots masked off by count after).
  uint32_t mask = 0;
  for (int i = 0; i < kCompactWidth; ++i) {
    const bool holds = (node.lower[i][0] <= qlo[0]) & (node.lower[i][1] <= qlo[1]) & (node.lower[i][2] <= qlo[2]) &
                       (qhi[0] <= node.upper[i][0]) & (qhi[1] <= node.upper[i][1]) & (qhi[2] <= node.upper[i][2]);
    mask |= uint32_t(holds) << i;
  }
  return node.count >= kCompactWidth ? mask : mask & ((1u << node.count) - 1u);
}
VS_HOST_DEVICE inline uint32_t children_holding(const CompactNode& node, const vec3f& q) {
  return children_holding(node, q, q);
}

// The index of the highest set bit of x (x > 0).
VS_HOST_DEVICE inline int highest_bit(uint32_t x) {
#ifdef __CUDA_ARCH__
  return 31 - __clz(int(x));
#else
  return 31 - __builtin_clz(x);
#endif
}

// A multi-leaf's bytes (CompactMesh::bytes from its sub-mesh's first_byte + first_byte): table_size little-endian
// uint16 sub-mesh-local vertex indices, then the corners as bytes into that table: pairs of tets (5 each: the shared
// face's three, then each tet's fourth), single tets (4 each), pyramids (5), wedges (6) and hexes (8). Element k of the
// leaf counts in that order.
struct CompactLeaf {
  uint32_t first_byte;  // from the sub-mesh's first byte
  uint16_t submesh;     // at most 65536 sub-meshes of 65536 vertices
  uint8_t table_last;   // distinct vertices - 1 (a leaf has 1 to 256)
  uint8_t tet_pairs;    // the first 2 * tet_pairs tets are pairs
  uint8_t counts[4];    // elements per type, type_slot order (tetra, pyramid, wedge, hexahedron)
  VS_HOST_DEVICE uint32_t table_size() const { return uint32_t(table_last) + 1u; }
  VS_HOST_DEVICE uint32_t element_count() const { return uint32_t(counts[0]) + counts[1] + counts[2] + counts[3]; }
  // Corner bytes of the leaf's elements (after the table).
  VS_HOST_DEVICE uint32_t corner_count() const {
    return 5u * tet_pairs + 4u * (counts[0] - 2u * tet_pairs) + 5u * counts[1] + 6u * counts[2] + 8u * counts[3];
  }
};
static_assert(sizeof(CompactLeaf) == 12);

struct CompactSubmesh {
  uint32_t first_vertex;  // into the local vertex array (and every field's values)
  uint32_t pad;
  uint64_t first_byte;  // of its leaves' bytes (a leaf's first_byte counts from here)
};

// The bytes of each part (bytes_per_element's breakdown).
struct CompactBytes {
  uint64_t vertices = 0, tables = 0, corners = 0, leaves = 0, nodes = 0, submeshes = 0, field = 0;
  uint64_t total() const { return vertices + tables + corners + leaves + nodes + submeshes + field; }
};

struct CompactMesh {
  HostArray<CompactNode> nodes;  // nodes[0] is the root
  HostArray<CompactLeaf> leaves;
  HostArray<uint8_t> bytes;  // every leaf's vertex table and corners (CompactLeaf)
  HostArray<CompactSubmesh> submeshes;
  HostArray<vec3f> vertices;              // local vertices, sub-mesh after sub-mesh
  HostArray<uint32_t> source_vertex;      // local vertex -> the reference vertex (gathers fields)
  uint64_t elements = 0, replicated = 0;  // local vertices beyond the mesh's own
  uint64_t paired_tets = 0;               // tets stored in pairs
  uint32_t leaf_parents = 0;              // index of the first node whose children are leaves
  CompactBytes bytes_by_part() const;
  // A field given per reference vertex, per local vertex (what the renderer samples).
  std::vector<float> gather(const float* reference_values) const;
};

CompactMesh build_compact_mesh(const UMesh& mesh);
// The 8-wide tree over the leaves in their order (nodes and leaf_parents), from their boxes.
void build_compact_tree(CompactMesh& c, const std::vector<box3f>& leaf_boxes);

// The face neighbours a CPU thread found last, direct-mapped by (leaf, element, face): rays of
// one tile (launch_cpu.h) cross the same faces, and finding a neighbour in another leaf (a search
// up the tree) costs more than the rest of a walk's step. Entries are of one view
// (CompactMeshView::id, new for every view made): a thread's cache is emptied when it walks
// another, so it never holds another mesh's neighbours.
struct NeighbourCache {
  static constexpr uint32_t kEntries = 8192;
  static constexpr uint64_t kNone = ~uint64_t(0);  // no neighbour (the mesh's boundary)
  uint64_t view = 0;
  uint64_t from[kEntries];  // 1 + (leaf * kMultiLeafSize + element) * 8 + face; 0: empty
  uint64_t to[kEntries];    // leaf * kMultiLeafSize + element, or kNone

  static uint32_t entry(uint64_t key) { return uint32_t((key * 0x9E3779B97F4A7C15ull) >> 51); }
  void clear() { memset(from, 0, sizeof(from)); }
};
static_assert(NeighbourCache::kEntries == 1u << 13);  // entry() keeps the hash's top 13 bits

// The element boxes of the leaves a thread searched last (CPU only, like NeighbourCache). A
// search tests the elements of every leaf whose box holds p, each decoded with its corners loaded
// before its box can refuse p; for a point outside every element (the samples of a ray before it
// enters the mesh or after it leaves) that is all of them, and the rays of a tile search the same
// leaves along the mesh's boundary. A cached box refuses p without the decoding. Entries are of one
// view (CompactMeshView::id, new for every view made), so they are never another mesh's.
struct LeafBoxCache {
  static constexpr uint32_t kEntries = 64;  // direct-mapped by leaf: neighbouring leaves do not collide
  uint64_t view = 0;
  uint32_t leaf[kEntries];  // leaf + 1; 0: empty
  box3f boxes[kEntries][kMultiLeafSize];
  void clear() { memset(leaf, 0, sizeof(leaf)); }
};

// The calling thread's cache of type C (NeighbourCache, LeafBoxCache), emptied when it last held
// another view's entries. On the heap: a thread's static TLS comes out of its stack, which
// threads started with small stacks (the view server's) cannot spare 100 KiB of.
template <typename C>
C& thread_cache(uint64_t view_id) {
  static thread_local std::unique_ptr<C> cache;
  if (!cache) cache = std::make_unique<C>();
  if (cache->view != view_id) {
    cache->clear();
    cache->view = view_id;
  }
  return *cache;
}

// Everything sampling reads (host or device pointers).
struct CompactMeshView {
  const CompactNode* nodes = nullptr;
  const CompactLeaf* leaves = nullptr;
  const uint8_t* bytes = nullptr;
  const CompactSubmesh* submeshes = nullptr;
  const vec3f* vertices = nullptr;
  uint32_t leaf_count = 0;
  uint32_t leaf_parents = 0;  // the first node whose children are leaves (leaf l: its child l % 8)
  // The tree's levels: level_first[0] = 0 (the root) .. level_first[levels - 1] = leaf_parents.
  // A node at position i of its level has its children at 8 i .. of the level below.
  static constexpr int kMaxLevels = 16;
  uint32_t level_first[kMaxLevels] = {};
  int levels = 0;
  // On the CPU, the thread's NeighbourCache and LeafBoxCache (false: every search made and every
  // element decoded; tests).
  bool thread_caches = true;
  uint64_t id = 0;             // unique per view made (compact_view): the key of the thread caches
  SubcellOccupancy occupancy;  // points it rules out are in no element's box: no leaf tested

  struct Hit {
    int64_t leaf = -1;
    uint32_t slot = 0;  // the element within the leaf
    uint32_t first_vertex = 0;
    uint16_t v[8];
    int n = 0;
    float w[8];
  };

  // Entry c of leaf's vertex table: a sub-mesh-local vertex index.
  VS_HOST_DEVICE const uint8_t* leaf_bytes(const CompactLeaf& leaf) const {
    return bytes + submeshes[leaf.submesh].first_byte + leaf.first_byte;
  }
  VS_HOST_DEVICE uint16_t table_entry(const CompactLeaf& leaf, uint32_t c) const {
    return entry_of(leaf_bytes(leaf), c);
  }
  // Entry c of the vertex table at `table` (16 bits, little-endian).
  VS_HOST_DEVICE static uint16_t entry_of(const uint8_t* table, uint32_t c) {
    return uint16_t(table[2u * c] | table[2u * c + 1u] << 8);
  }
  VS_HOST_DEVICE const uint8_t* corners(const CompactLeaf& leaf) const {
    return leaf_bytes(leaf) + 2u * leaf.table_size();
  }

  // Element k of the leaf: its vertex count, and its corners as table bytes (corner) and as
  // sub-mesh-local vertex indices (v).
  VS_HOST_DEVICE int element(const CompactLeaf& leaf, uint32_t k, uint8_t* corner, uint16_t* v) const {
    const uint8_t* c = corners(leaf);
    int n = 4;
    const uint32_t paired = 2u * leaf.tet_pairs;
    if (k < paired) {
      const uint8_t* pair = c + (k / 2) * 5u;
      corner[0] = pair[0], corner[1] = pair[1], corner[2] = pair[2], corner[3] = pair[3 + (k & 1u)];
    } else {
      c += 5u * leaf.tet_pairs;
      k -= paired;
      const uint32_t counts[4] = {leaf.counts[0] - paired, leaf.counts[1], leaf.counts[2], leaf.counts[3]};
      constexpr int kVertices[4] = {4, 5, 6, 8};
      for (int type = 0; type < 4; ++type) {
        n = kVertices[type];
        if (k < counts[type]) break;
        k -= counts[type];
        c += counts[type] * uint32_t(n);
      }
      c += k * uint32_t(n);
      for (int i = 0; i < n; ++i) corner[i] = c[i];
    }
    for (int i = 0; i < n; ++i) v[i] = table_entry(leaf, corner[i]);
    return n;
  }

  // The corner positions of an element whose sub-mesh vertices are v[0..n) (element() gives them).
  struct CornerPoints {
    vec3f x[8];
    VS_HOST_DEVICE box3f box(int n) const {
      return corners_box(n, [&](int i) -> const vec3f& { return x[i]; });
    }
  };
  VS_HOST_DEVICE CornerPoints corner_points(uint32_t first_vertex, const uint16_t* v, int n) const {
    CornerPoints c;
    for (int i = 0; i < n; ++i) c.x[i] = vertices[first_vertex + v[i]];
    return c;
  }

  // Tests element k of leaf l (hit and best as for UMeshView::consider: a strict hit wins, else
  // the nearest within the tolerance); true on a strict hit.
  VS_HOST_DEVICE bool test_element(uint32_t l, uint32_t k, const vec3f& p, Hit& hit, float& best) const {
    const CompactLeaf& leaf = leaves[l];
    uint8_t corner[8];
    uint16_t v[8];
    const int n = element(leaf, k, corner, v);
    const uint32_t base = submeshes[leaf.submesh].first_vertex;
    const CornerPoints x = corner_points(base, v, n);
    float w[8], outside;
    if (!x.box(n).contains(p) || !shape::locate_in_element(n, x.x, p, w, &outside, nullptr, true) || !(outside < best))
      return false;
    best = outside;
    hit.leaf = l;
    hit.slot = k;
    hit.first_vertex = base;
    hit.n = n;
    for (int i = 0; i < n; ++i) hit.v[i] = v[i], hit.w[i] = w[i];
    return outside <= 0.f;
  }

  // Tests the elements of leaf l, nearest to element `start` first (elements are in Morton
  // order: the previous sample's neighbours are close by); true on a strict hit.
  VS_HOST_DEVICE bool test_leaf(uint32_t l, const vec3f& p, Hit& hit, float& best, uint32_t start = 0) const {
    const uint32_t count = leaves[l].element_count();
    if (start >= count) start = 0;
    const box3f* boxes = nullptr;  // the elements' boxes where a thread cache has them
#ifndef __CUDA_ARCH__
    if (thread_caches) boxes = cached_element_boxes(l);
#endif
    auto test = [&](uint32_t k) { return (!boxes || boxes[k].contains(p)) && test_element(l, k, p, hit, best); };
    for (uint32_t d = 0; d < count; ++d) {
      if (start + d < count && test(start + d)) return true;
      if (d > 0 && d <= start && test(start - d)) return true;
      if (start + d >= count && d > start) break;
    }
    return false;
  }

#ifndef __CUDA_ARCH__
  // The boxes of leaf l's elements (as test_element makes them), from the thread's LeafBoxCache.
  const box3f* cached_element_boxes(uint32_t l) const {
    LeafBoxCache& cache = thread_cache<LeafBoxCache>(id);
    const uint32_t at = l % LeafBoxCache::kEntries;
    if (cache.leaf[at] != l + 1) {
      const CompactLeaf& leaf = leaves[l];
      const uint32_t base = submeshes[leaf.submesh].first_vertex;
      for (uint32_t k = 0; k < leaf.element_count(); ++k) {
        uint8_t corner[8];
        uint16_t v[8];
        const int n = element(leaf, k, corner, v);
        cache.boxes[at][k] = corner_points(base, v, n).box(n);
      }
      cache.leaf[at] = l + 1;
    }
    return cache.boxes[at];
  }
#endif

  // Calls visit(leaf) for every leaf whose box holds the box [lo, hi] below node `top` but not
  // below its child `skip` (-1: none), until visit returns true (then true).
  template <typename Visit>
  VS_HOST_DEVICE bool for_each_leaf_holding_below(uint32_t top, int skip, const vec3f& lo, const vec3f& hi,
                                                  Visit&& visit) const {
    uint32_t stack[64];
    int depth = 0;
    if (!nodes) return false;
    stack[depth++] = top;
    while (depth > 0) {
      const uint32_t at = stack[--depth];
      const CompactNode& node = nodes[at];
      uint32_t holding = children_holding(node, lo, hi);
      if (at == top && skip >= 0) holding &= ~(1u << skip);
      // Over the set bits only, highest first (a loop over all eight mispredicts its branches).
      for (; holding != 0; holding &= ~(1u << highest_bit(holding))) {
        const uint32_t child = node.first + uint32_t(highest_bit(holding));
        if (node.leaf_children) {
          if (visit(child)) return true;
        } else if (depth < 64) {
          stack[depth++] = child;
        }
      }
    }
    return false;
  }
  template <typename Visit>
  VS_HOST_DEVICE bool for_each_leaf_holding(const vec3f& q, Visit&& visit) const {
    return for_each_leaf_holding_below(0, -1, q, q, visit);
  }

  // The same leaves but those near leaf l first, and without l: up the tree from l, each
  // ancestor's subtree without the child already searched (every other leaf once, so the set is
  // for_each_leaf_holding's; a neighbour of l is mostly found in its parent's or grandparent's).
  template <typename Visit>
  VS_HOST_DEVICE bool for_each_leaf_holding_near(uint32_t l, const vec3f& q, Visit&& visit) const {
    return for_each_leaf_holding_near(l, q, q, visit);
  }
  template <typename Visit>
  VS_HOST_DEVICE bool for_each_leaf_holding_near(uint32_t l, const vec3f& lo, const vec3f& hi, Visit&& visit) const {
    if (levels <= 0) return false;
    uint32_t node = leaf_parents + l / kCompactWidth;
    int skip = int(l % kCompactWidth);
    for (int level = levels - 1;; --level) {
      if (for_each_leaf_holding_below(node, skip, lo, hi, visit)) return true;
      if (level == 0) return false;
      const uint32_t position = node - level_first[level];
      skip = int(position % kCompactWidth);
      node = level_first[level - 1] + position / kCompactWidth;
    }
  }

  VS_HOST_DEVICE bool search(const vec3f& p, Hit& hit, float& best) const {
    return for_each_leaf_holding(p, [&](uint32_t l) { return test_leaf(l, p, hit, best); });
  }

  // The element of leaf l, other than element `skip`, whose corners include every corner of
  // `face` (bytes of the leaf's table; a triangle repeats face[0] as face[3]), or -1: the
  // neighbour across a face is found by comparing corners, with no adjacency stored and no
  // geometry read. An element's corners are distinct, so the number of its corners that are any
  // of the face's is the number of the face's corners it holds. The comparisons run over the
  // leaf's whole corner run in one loop the compiler vectorizes (the walk's hot loop).
  VS_HOST_DEVICE int32_t face_neighbour_in_leaf(uint32_t l, uint32_t skip, const uint8_t* face, int face_size) const {
    const CompactLeaf& leaf = leaves[l];
    const uint8_t* c = corners(leaf);
    const uint32_t total = leaf.corner_count();
    uint8_t held[kMultiLeafSize * 8];
    const uint8_t f0 = face[0], f1 = face[1], f2 = face[2], f3 = face[3];
    for (uint32_t i = 0; i < total; ++i) held[i] = uint8_t((c[i] == f0) | (c[i] == f1) | (c[i] == f2) | (c[i] == f3));
    uint32_t k = 0, at = 0;
    for (uint32_t pair = 0; pair < leaf.tet_pairs; ++pair, k += 2, at += 5) {
      const int shared = held[at] + held[at + 1] + held[at + 2];
      if (shared + held[at + 3] == face_size && k != skip) return int32_t(k);
      if (shared + held[at + 4] == face_size && k + 1 != skip) return int32_t(k + 1);
    }
    // Single tets: their four flags are one 32-bit word, summed by one multiply.
    for (uint32_t e = 2u * leaf.tet_pairs; e < leaf.counts[0]; ++e, ++k, at += 4) {
      uint32_t word;
      memcpy(&word, held + at, 4);
      if (int((word * 0x01010101u) >> 24) == face_size && k != skip) return int32_t(k);
    }
    constexpr int kVertices[4] = {4, 5, 6, 8};
    for (int type = 1; type < 4; ++type) {
      const int n = kVertices[type];
      for (uint32_t e = 0; e < leaf.counts[type]; ++e, ++k, at += uint32_t(n)) {
        int matched = 0;
        for (int i = 0; i < n; ++i) matched += held[at + uint32_t(i)];
        if (matched == face_size && k != skip) return int32_t(k);
      }
    }
    return -1;
  }

  // The bytes of leaf l's table whose vertices are the face's four (a triangle repeats its first
  // as the fourth), by equal(table entry, i) for face vertex i; false when one is not in it (then
  // no element of the leaf holds the face). One pass without exits (the compiler vectorizes the
  // index compares): each face vertex's position in the table plus one, 0 where absent (most
  // leaves asked hold the face's box but not the face).
  template <typename Equal>
  VS_HOST_DEVICE bool face_in_table_where(uint32_t l, uint8_t* face_bytes, Equal&& equal) const {
    const CompactLeaf& leaf = leaves[l];
    const uint8_t* table = leaf_bytes(leaf);
    uint32_t at0 = 0, at1 = 0, at2 = 0, at3 = 0;
    for (uint32_t t = 0; t < leaf.table_size(); ++t) {
      const uint32_t v = uint32_t(table[2u * t]) | uint32_t(table[2u * t + 1u]) << 8;
      at0 = equal(v, 0) ? t + 1u : at0, at1 = equal(v, 1) ? t + 1u : at1;
      at2 = equal(v, 2) ? t + 1u : at2, at3 = equal(v, 3) ? t + 1u : at3;
    }
    if (!(at0 && at1 && at2 && at3)) return false;
    face_bytes[0] = uint8_t(at0 - 1u), face_bytes[1] = uint8_t(at1 - 1u);
    face_bytes[2] = uint8_t(at2 - 1u), face_bytes[3] = uint8_t(at3 - 1u);
    return true;
  }
  // By sub-mesh-local indices (face[3] repeats face[0] for a triangle): leaves of the face's sub-mesh.
  VS_HOST_DEVICE bool face_in_table(uint32_t l, const uint16_t* face, uint8_t* face_bytes) const {
    return face_in_table_where(l, face_bytes, [&](uint32_t v, int i) { return v == face[i]; });
  }
  // By position (points[3] repeats points[0] for a triangle): leaves of another sub-mesh, where
  // the face's vertices are replicated with the same coordinates.
  VS_HOST_DEVICE bool face_in_table_at(uint32_t l, const vec3f* points, uint8_t* face_bytes) const {
    const vec3f* local = vertices + submeshes[leaves[l].submesh].first_vertex;
    return face_in_table_where(l, face_bytes, [&](uint32_t v, int i) { return local[v] == points[i]; });
  }

  // The element across face `face` of element k of leaf l (its corners and vertices given): in
  // the same leaf, or in another leaf whose box holds the face. False at the mesh's boundary.
  VS_HOST_DEVICE bool face_neighbour(uint32_t& l, uint32_t& k, const uint8_t* corner, const uint16_t* v, int n,
                                     int face) const {
    // A paired tet's face off its apex (corner 3: local face 3) is the face it shares with its pair.
    if (n == 4 && face == 3 && k < 2u * leaves[l].tet_pairs) return k ^= 1u, true;
#ifndef __CUDA_ARCH__
    if (thread_caches) {
      NeighbourCache& cache = thread_cache<NeighbourCache>(id);
      const uint64_t key = 1u + (uint64_t(l) * kMultiLeafSize + k) * 8u + uint64_t(face);
      const uint32_t at = NeighbourCache::entry(key);
      if (cache.from[at] == key) {
        const uint64_t to = cache.to[at];
        if (to == NeighbourCache::kNone) return false;
        const uint64_t to_leaf = to / kMultiLeafSize;
        // Entries are of this view's mesh; checked anyway, so that no entry can lead outside it.
        if (to_leaf < leaf_count && to % kMultiLeafSize < leaves[to_leaf].element_count())
          return l = uint32_t(to_leaf), k = uint32_t(to % kMultiLeafSize), true;
      }
      const bool found = search_face_neighbour(l, k, corner, v, n, face);
      cache.from[at] = key;
      cache.to[at] = found ? uint64_t(l) * kMultiLeafSize + k : NeighbourCache::kNone;
      return found;
    }
#endif
    return search_face_neighbour(l, k, corner, v, n, face);
  }
  // face_neighbour without the cache.
  VS_HOST_DEVICE bool search_face_neighbour(uint32_t& l, uint32_t& k, const uint8_t* corner, const uint16_t* v, int n,
                                            int face) const {
    const shape::LocalFace f = shape::local_face(n, face);
    uint8_t face_bytes[4];
    uint16_t face_vertices[4];
    for (int i = 0; i < 4; ++i) {
      face_bytes[i] = corner[f.v[i < f.count ? i : 0]];
      face_vertices[i] = v[f.v[i < f.count ? i : 0]];
    }
    int32_t next = face_neighbour_in_leaf(l, k, face_bytes, f.count);
    if (next >= 0) return k = uint32_t(next), true;
    // Another leaf: the neighbour's leaf box holds the face, so only leaves holding the face's
    // box are compared (fewer than those holding a point of it), nearest in the tree first; in
    // another sub-mesh (where a walk would otherwise end) by the face's vertex positions.
    const uint32_t submesh = leaves[l].submesh;
    vec3f points[4];
    box3f face_box = box3f::make_empty();
    for (int i = 0; i < 4; ++i) {
      points[i] = vertices[submeshes[submesh].first_vertex + face_vertices[i]];
      face_box.extend(points[i]);
    }
    return for_each_leaf_holding_near(l, face_box.lower, face_box.upper, [&](uint32_t other) {
      uint8_t other_bytes[4];
      const bool holds = leaves[other].submesh == submesh ? face_in_table(other, face_vertices, other_bytes)
                                                          : face_in_table_at(other, points, other_bytes);
      next = holds ? face_neighbour_in_leaf(other, kNoSkip, other_bytes, f.count) : -1;
      if (next >= 0) l = other, k = uint32_t(next);
      return next >= 0;
    });
  }
  static constexpr uint32_t kNoSkip = 0xffffffffu;

  // The face of the element with corners x whose centre lies most in p's direction from the
  // element's centre: the way on where Newton gave none (it diverged or did not converge, far from
  // a curved element), so that the walk goes on instead of ending in a search of leaves.
  VS_HOST_DEVICE static int face_towards(int n, const vec3f* x, const vec3f& p) {
    vec3f centre(0.f);
    for (int i = 0; i < n; ++i) centre = centre + x[i];
    centre = centre * (1.f / float(n));
    int best = -1;
    float best_reach = -INFINITY;
    for (int face = 0; face < shape::face_count(n); ++face) {
      const shape::LocalFace f = shape::local_face(n, face);
      vec3f c(0.f);
      for (int i = 0; i < f.count; ++i) c = c + x[f.v[i]];
      const vec3f out = c * (1.f / float(f.count)) - centre;
      // p's distance along the face's direction, in units of the face's distance.
      const float reach = dot(p - centre, out) / dot(out, out);
      if (reach > best_reach) best = face, best_reach = reach;
    }
    return best_reach > 0.f ? best : -1;
  }

  // The ray's note of where its last sample was (RayState::hint, volume.h): the element (leaf *
  // kMultiLeafSize + slot; -1: none), the solve that located that sample there
  // (shape::KeptSolve), and the element's corners as the walk reads them, so that the next
  // sample's first test, in that element, decodes and loads nothing.
  struct Hint {
    int64_t element = -1;
    shape::KeptSolve solve;
    uint8_t corner[8];
    uint16_t v[8];
    uint32_t first_vertex = 0;
    bool in_hole = false;  // as UMeshView::Hint::in_hole, but the element stays: the search starts near it
  };

  // Walks from the hint's element towards p across the faces p lies beyond (as UMeshView::walk,
  // with neighbours found by face_neighbour): true with the hit when an element holds p strictly
  // within kMaxWalk steps (the hint then holds it).
  VS_HOST_DEVICE bool walk(Hint& hint, const vec3f& p, Hit& hit) const {
    constexpr int kMaxWalk = 8;
    uint32_t l = uint32_t(hint.element / kMultiLeafSize), k = uint32_t(hint.element % kMultiLeafSize);
    int step = 0;
    if (hint.solve.n > 0) {  // the first step from the kept solve
      float outside = INFINITY;
      int face = -1, n = 0;
      if (hint.solve.locate_again(p, hit.w, &outside, &face, n) && outside <= 0.f) {
        hint.solve.n = n;
        hit.leaf = l, hit.slot = k, hit.first_vertex = hint.first_vertex, hit.n = n;
        for (int i = 0; i < n; ++i) hit.v[i] = hint.v[i];
        return true;
      }
      if (face < 0) face = face_towards(n, corner_points(hint.first_vertex, hint.v, n).x, p);
      if (face < 0 || !face_neighbour(l, k, hint.corner, hint.v, n, face)) return false;
      ++step;
    }
    for (; step < kMaxWalk; ++step) {
      const int n = element(leaves[l], k, hint.corner, hint.v);
      const uint32_t base = submeshes[leaves[l].submesh].first_vertex;
      const CornerPoints x = corner_points(base, hint.v, n);
      float outside = INFINITY;
      int face = -1;
      if (hint.solve.locate(n, x.x, p, hit.w, &outside, &face) && outside <= 0.f) {
        hint.element = l * int64_t(kMultiLeafSize) + k;
        hint.solve.n = n;
        hint.first_vertex = base;
        hit.leaf = l, hit.slot = k, hit.first_vertex = base, hit.n = n;
        for (int i = 0; i < n; ++i) hit.v[i] = hint.v[i];
        return true;
      }
      if (face < 0) face = face_towards(n, x.x, p);
      if (face < 0 || !face_neighbour(l, k, hint.corner, hint.v, n, face)) return false;
    }
    return false;
  }

  // The element holding p: a walk from the ray's previous element first; where it ends without a
  // strict hit, that element's leaf from there out, then every other leaf holding p, near ones
  // first (so the result is search's: a strict hit wins, none is missed). The element found is
  // the next hint.
  VS_HOST_DEVICE Hit locate(const vec3f& p, Hint& hint) const {
    Hit hit;
    float best = INFINITY;
    if (hint.element >= 0 && !hint.in_hole && walk(hint, p, hit)) return hit;
    hit = Hit{};
    hint.in_hole = true;
    if (occupancy.rules_out(p)) return hit;
    if (hint.element >= 0) {
      const uint32_t leaf = uint32_t(hint.element / kMultiLeafSize);
      if (!test_leaf(leaf, p, hit, best, uint32_t(hint.element % kMultiLeafSize)))
        for_each_leaf_holding_near(leaf, p, [&](uint32_t other) { return test_leaf(other, p, hit, best); });
    } else {
      search(p, hit, best);
    }
    if (hit.leaf >= 0) hint.element = hit.leaf * int64_t(kMultiLeafSize) + hit.slot, hint.in_hole = false;
    return hit;
  }

  VS_HOST_DEVICE float sample(const float* values, const vec3f& p, Hint& hint) const {
    const Hit hit = locate(p, hint);
    if (hit.leaf < 0) return NAN;
    float f = 0.f;
    for (int i = 0; i < hit.n; ++i) f += hit.w[i] * values[hit.first_vertex + hit.v[i]];
    return f;
  }
  VS_HOST_DEVICE float sample(const float* values, const vec3f& p) const {
    Hint no_hint;
    return sample(values, p, no_hint);
  }
};

// The view of a compact mesh whose arrays are at the given pointers (host or device); `nodes`
// is the host copy of the tree (its levels are read from it).
CompactMeshView compact_view(const CompactMesh& host, const CompactNode* nodes, const CompactLeaf* leaves,
                             const uint8_t* bytes, const CompactSubmesh* submeshes, const vec3f* vertices);
// The view of a host-resident compact mesh.
inline CompactMeshView view_of(const CompactMesh& c) {
  return compact_view(c, c.nodes.data(), c.leaves.data(), c.bytes.data(), c.submeshes.data(), c.vertices.data());
}

}  // namespace vs
