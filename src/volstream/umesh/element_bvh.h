// The reference encoding's acceleration structure for point location: a binary BVH over the
// elements' boxes with up to kElementLeafSize elements per leaf, addressed through an item list
// (the layout of paper 002's baseline: 32 B nodes plus 4 B per element of item list). Built by
// median splits on the longest axis of the centroids (balanced: depth ~ log2(elements / leaf)).
// Children of an inner node are adjacent (first, first + 1).
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/core/math.h"
#include "volstream/umesh/macro_grid.h"
#include "volstream/umesh/shape.h"
#include "volstream/umesh/umesh.h"

namespace vs {

inline constexpr uint32_t kElementLeafSize = 4;

struct ElementBvhNode {
  box3f box;
  uint32_t first;  // inner: left child (right = first + 1); leaf: first item
  uint32_t count;  // 0: inner node; else the leaf's item count
};

// Everything a walk step through a tet reads, in one 64-byte line: corner 0 and the rows that
// give its barycentric weights at p with three dot products (Cramer's cofactor rows divided by
// the determinant, so no divide), and its face neighbours (face i opposite corner i, as in the
// adjacency). Found in a tet, a walk fetches its neighbours' records (and their elements, whose
// corner indices the sample's interpolation reads) while the ray composites: the next sample
// lies in one of them about half the time. Without them a step is a chain of dependent misses
// (element, corners, neighbour row). Convert stores them (mesh_tet_walk.bin) and the renderer
// maps them, or builds them for a mesh without them (tet_walk_records, mesh_accel.h); another
// type's record, or a degenerate tet's, has NaN rows (is_tet() false) and that element is
// walked through its corners as before. The layout is the file's (docs/formats.md).
struct alignas(64) TetWalkRecord {
  vec3f origin;
  vec3f rows[3];
  uint32_t neighbor[4];
  VS_HOST_DEVICE bool is_tet() const { return rows[0].x == rows[0].x; }
};
static_assert(sizeof(TetWalkRecord) == 64);

struct ElementBvh {
  HostArray<ElementBvhNode> nodes;  // nodes[0] is the root
  HostArray<uint32_t> items;        // element indices in leaf order
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
  const uint32_t* neighbors = nullptr;      // kMaxFaces per element (umesh/adjacency.h); null: no walk
  const TetWalkRecord* tet_walk = nullptr;  // per element (with neighbors), or null: tets walked by corners
  SubcellOccupancy occupancy;               // points it rules out are in no element: no search
  static constexpr uint32_t kNoNeighborIndex = 0xffffffffu;

  // Weights of element e at p (false: p is outside it, or outside its corners' box, which the
  // BVH's boxes are made of). `outside` as in shape::locate_in_element. Newton gives up as soon
  // as it shows p outside (early_out): a search's candidates mostly do not hold p (19% of the
  // mixed demo's haze samples lie in no element at all), and a point inside or within the
  // tolerance gets the same answer either way.
  VS_HOST_DEVICE bool in_element(uint32_t e, const vec3f& p, float* w, float* outside) const {
    const UElement& el = elements[e];
    const int n = el.vertex_count();
    vec3f x[8];
    box3f b = box3f::make_empty();
    for (int i = 0; i < n; ++i) {
      x[i] = vertices[el.v[i]];
      b.extend(x[i]);
    }
    return b.contains(p) && shape::locate_in_element(n, x, p, w, outside, nullptr, true);
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

  // Every element holding p, through the BVH (hit and best as in consider): true on a strict hit.
  VS_HOST_DEVICE bool search(const vec3f& p, ElementHit& hit, float& best) const {
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const ElementBvhNode& node = nodes[stack[--top]];
      if (!node.box.contains(p)) continue;
      if (node.count == 0) {
        stack[top++] = node.first + 1;
        stack[top++] = node.first;
        continue;
      }
      for (uint32_t k = 0; k < node.count; ++k)
        if (consider(items[node.first + k], p, hit, best)) return true;
    }
    return false;
  }

  VS_HOST_DEVICE ElementHit locate(const vec3f& p) const {
    ElementHit hit;
    float best = INFINITY;
    if (node_count > 0 && !occupancy.rules_out(p)) search(p, hit, best);
    return hit;
  }

  // The ray's note of where its last sample was (RayState::hint, volume.h): the element, and
  // the solve that located that sample there (shape::KeptSolve), so that the next sample's
  // first test, in that element, loads no corners (none where a tet's walk record located it:
  // the record is the solve, and in cache).
  struct Hint {
    int64_t element = -1;
    shape::KeptSolve solve;
    // The last sample lay in no element (a hole, a notch, beyond the mesh inside its grid; the
    // element is then -1): the next one goes to the search without a walk, which from the
    // element before the hole would only reach the boundary again (Newton's solves on the way),
    // nor one from its macrocell's start (MeshVolume::start_walk).
    bool in_hole = false;
  };

  static constexpr int kMaxWalk = 8;
  // Walks from the hint's element towards p across the faces p lies beyond (face adjacency):
  // true with the hit when an element holds p strictly within kMaxWalk steps (the hint then
  // holds it); false at the mesh's boundary, an unmatched face, or a point too far to tell the way.
  VS_HOST_DEVICE bool walk(Hint& hint, const vec3f& p, ElementHit& hit) const {
    uint32_t e = uint32_t(hint.element);
    int step = 0;
    if (hint.solve.n > 0) {  // the first step from the kept solve
      float outside = INFINITY;
      int face = -1, n = 0;
      if (hint.solve.locate_again(p, hit.w, &outside, &face, n) && outside <= 0.f) {
        hit.element = e;
        hint.solve.n = n;
        return true;
      }
      if (!cross_face(e, face)) return false;
      ++step;
    }
    for (; step < kMaxWalk; ++step) {
      if (tet_walk && tet_walk[e].is_tet()) {
        if (record_step(e, p, hit.w)) {
          prefetch_neighbor_records(tet_walk[e]);
          hit.element = e;
          hint.element = e;
          hint.solve.n = 0;  // the record is the kept solve
          return true;
        }
        if (e == kNoNeighborIndex) return false;
        continue;
      }
      const UElement& el = elements[e];
      const int n = el.vertex_count();
      vec3f x[8];
      for (int i = 0; i < n; ++i) x[i] = vertices[el.v[i]];
      float outside = INFINITY;
      int face = -1;
      if (hint.solve.locate(n, x, p, hit.w, &outside, &face) && outside <= 0.f) {
        hit.element = e;
        hint.element = e;
        hint.solve.n = n;
        prefetch_neighbors(e);
        return true;
      }
      if (!cross_face(e, face)) return false;
    }
    return false;
  }

  // One step of a walk through tet e's record: true when p lies strictly in e (w[0..4) its
  // weights); else e becomes the neighbour across the face p lies beyond most (kNoNeighborIndex:
  // none). Where p is found, the caller fetches the neighbours' records.
  VS_HOST_DEVICE bool record_step(uint32_t& e, const vec3f& p, float* w) const {
    const TetWalkRecord& t = tet_walk[e];
    int face = -1;
    if (tet_record_weights(t, p, w, face)) return true;
    e = t.neighbor[face];
    return false;
  }

  // sample(values, p, hint) where the ray's last sample was in a tet with a walk record and the
  // walk to p crosses only such tets, the common case on a tet mesh: the weights go straight to
  // the tet's four corners, without the hit record and the general walk around them (12% of a
  // tet render's instructions). False where the general path must decide; the hint then holds
  // the last element reached, where that walk goes on.
  VS_FORCE_INLINE VS_HOST_DEVICE bool sample_through_tets(const float* values, const vec3f& p, Hint& hint,
                                                          float& f) const {
    if (!tet_walk || hint.element < 0 || hint.solve.n > 0) return false;
    uint32_t e = uint32_t(hint.element);
    for (int step = 0; step < kMaxWalk && tet_walk[e].is_tet(); ++step) {
      float w[4];
      const uint32_t from = e;
      if (record_step(e, p, w)) {
        // A tet the ray stays in had its neighbours fetched when the ray entered it.
        if (step > 0) prefetch_neighbor_records(tet_walk[e]);
        hint.element = e;
        const uint32_t* v = elements[e].v;
        f = w[0] * values[v[0]] + w[1] * values[v[1]] + w[2] * values[v[2]] + w[3] * values[v[3]];
        return true;
      }
      if (e == kNoNeighborIndex) {
        hint.element = from;  // the general walk meets the same boundary face, then searches
        return false;
      }
    }
    hint.element = e;
    return false;
  }

  // Weights at p from a tet's record (w[0..4)) and the face p lies beyond most (as
  // shape::tet_weights, with the division done beforehand); true when p is strictly inside, as
  // the walk asks (a point within the tolerance may lie strictly in the neighbour).
  VS_HOST_DEVICE static bool tet_record_weights(const TetWalkRecord& t, const vec3f& p, float* w, int& face) {
    const vec3f b = p - t.origin;
    face = shape::tet_weights_of({dot(b, t.rows[0]), dot(b, t.rows[1]), dot(b, t.rows[2])}, w);
    return w[face] >= 0.f;
  }

  VS_HOST_DEVICE void prefetch_neighbor_records(const TetWalkRecord& t) const {
#if !defined(__CUDA_ARCH__)
    for (uint32_t next : t.neighbor)
      if (next != kNoNeighborIndex) __builtin_prefetch(tet_walk + next), __builtin_prefetch(elements + next);
#else
    (void)t;
#endif
  }

  // The ray's next samples leave e across one of its faces about every other sample, and the
  // neighbour table is the walk's cache miss (random rows of 24 MB on 1 M elements): its row
  // is fetched while the ray composites the sample that found e.
  VS_HOST_DEVICE void prefetch_neighbors(uint32_t e) const {
#if !defined(__CUDA_ARCH__)
    __builtin_prefetch(neighbors + uint64_t(e) * shape::kMaxFaces);
#endif
  }

  // e becomes its neighbour across `face`; false when there is none (or no face: -1).
  VS_HOST_DEVICE bool cross_face(uint32_t& e, int face) const {
    if (face < 0) return false;
    e = neighbors[uint64_t(e) * shape::kMaxFaces + uint64_t(face)];
    return e != kNoNeighborIndex;
  }

  // locate(p) starting from the hint (the ray's previous sample's element; -1: none):
  // consecutive samples are close, so a walk of a step or two over face neighbours usually
  // finds p; where it does not (the boundary, an unmatched face, a long way), the BVH search
  // decides, so the result is locate(p)'s (a strict hit wins; none may be missed). The element
  // found is the next hint (none: -1, and in_hole).
  VS_HOST_DEVICE ElementHit locate(const vec3f& p, Hint& hint) const {
    ElementHit hit;
    if (hint.element >= 0 && neighbors && walk(hint, p, hit)) return hit;
    hit = locate(p);
    hint.element = hit.element;
    hint.in_hole = hit.element < 0;
    return hit;
  }

  // The field's value at p, NaN outside every element.
  VS_HOST_DEVICE float sample(const float* values, const vec3f& p) const {
    Hint no_hint;
    return sample(values, p, no_hint);
  }
  // The walk through tets inlined into the integrator's sample loop; the general path is a call.
  VS_FORCE_INLINE VS_HOST_DEVICE float sample(const float* values, const vec3f& p, Hint& hint) const {
    float f = 0.f;
    if (sample_through_tets(values, p, hint, f)) return f;
    return sample_located(values, p, hint);
  }
  VS_HOST_DEVICE float sample_located(const float* values, const vec3f& p, Hint& hint) const {
    float f = 0.f;
    const ElementHit hit = locate(p, hint);
    if (hit.element < 0) return NAN;
    const UElement& el = elements[hit.element];
    const int n = el.vertex_count();
    for (int i = 0; i < n; ++i) f += hit.w[i] * values[el.v[i]];
    return f;
  }
};

}  // namespace vs
