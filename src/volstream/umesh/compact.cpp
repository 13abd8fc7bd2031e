#include "volstream/umesh/compact.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <span>
#include <unordered_map>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"

namespace vs {
namespace {

// The median splits end in runs of half a multi-leaf; a leaf is the two runs of one split where
// they hold tets alone, else each run is a leaf (leaf_end).
constexpr size_t kClusterRun = kMultiLeafSize / 2;
static_assert(kClusterRun * 8 <= 256 && kMultiLeafSize * 4 <= 256, "a leaf's corners must fit a byte");

// Splits elements [begin, end) of `order` at the median of their centres along the longest axis
// of the centres' box, recursively, down to runs of kClusterRun: each run is a compact cluster
// (few faces to other leaves, so a walk mostly stays in its leaf, and leaf boxes overlap little),
// and consecutive runs are close in space (the tree above groups them in eights). Split points
// are multiples of kMultiLeafSize down to groups of one leaf, which split once more in two runs,
// so every leaf-sized group but the last is full and its runs are its halves.
void median_split_order(const std::vector<vec3f>& centre, uint32_t* begin, uint32_t* end) {
  const size_t n = size_t(end - begin);
  if (n <= kClusterRun) return;
  box3f bounds = box3f::make_empty();
  for (const uint32_t* e = begin; e != end; ++e) bounds.extend(centre[*e]);
  const vec3f extent = bounds.size();
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
  const size_t groups = (n + kMultiLeafSize - 1) / kMultiLeafSize;
  uint32_t* middle = begin + (n <= kMultiLeafSize ? kClusterRun : (groups / 2) * kMultiLeafSize);
  std::nth_element(begin, middle, end, [&](uint32_t a, uint32_t b) { return centre[a][axis] < centre[b][axis]; });
  if (n > 65536) {
    tbb::parallel_invoke([&] { median_split_order(centre, begin, middle); },
                         [&] { median_split_order(centre, middle, end); });
  } else {
    median_split_order(centre, begin, middle);
    median_split_order(centre, middle, end);
  }
}

std::vector<uint32_t> cluster_order(const UMesh& mesh) {
  const size_t n = mesh.elements.size();
  std::vector<vec3f> centre(n);
  parallel_for("element centres", int64_t(n), [&](int64_t e) {
    centre[size_t(e)] = element_box(mesh.vertices.data(), mesh.elements[size_t(e)]).center();
  });
  std::vector<uint32_t> order(n);
  for (size_t e = 0; e < n; ++e) order[e] = uint32_t(e);
  median_split_order(centre, order.data(), order.data() + n);
  return order;
}

// Quantizes `child` relative to the node box [origin, origin + 255 * scale], rounded outwards,
// and widened by a step where float rounding would still leave part of the child outside.
void quantize(CompactNode& node, int i, const box3f& child) {
  // A step count in [0, 255], clamped before the conversion (a NaN or huge float has no int).
  auto step = [](float x) { return x > 0.f ? (x < 255.f ? int(x) : 255) : 0; };
  for (int a = 0; a < 3; ++a) {
    const float s = node.scale[a];
    int lo = s > 0.f ? step(std::floor((child.lower[a] - node.origin[a]) / s)) : 0;
    int hi = s > 0.f ? step(std::ceil((child.upper[a] - node.origin[a]) / s)) : 0;
    while (lo > 0 && node.origin[a] + float(lo) * s > child.lower[a]) --lo;
    while (hi < 255 && node.origin[a] + float(hi) * s < child.upper[a]) ++hi;
    node.lower[i][a] = uint8_t(lo);
    node.upper[i][a] = uint8_t(hi);
  }
}

// A node over `children` boxes (at most kCompactWidth): its own box is their union, slightly
// grown so that the top quantization step reaches the union's upper corner in float.
CompactNode make_node(const box3f* children, int count, uint32_t first, bool leaf_children, box3f& bounds) {
  bounds = box3f::make_empty();
  for (int i = 0; i < count; ++i) bounds.extend(children[i]);
  CompactNode node{};
  node.origin = bounds.lower;
  const vec3f extent = bounds.size();
  for (int a = 0; a < 3; ++a) {
    // A few ulps of the coordinates more than the extent: the top step must reach the upper
    // corner in float also where the box is tiny against its distance from the origin.
    const float ulps = 4.f * FLT_EPSILON * std::max(std::fabs(bounds.lower[a]), std::fabs(bounds.upper[a]));
    node.scale[a] = extent[a] > 0.f ? (extent[a] * (1.f + 1e-6f) + ulps) / 255.f : 0.f;
  }
  for (int i = 0; i < count; ++i) quantize(node, i, children[i]);
  node.first = first;
  node.count = uint8_t(count);
  node.leaf_children = leaf_children ? 1 : 0;
  return node;
}

// Two tets of a leaf that share a face, and the corner of each off that face.
struct TetPair {
  uint32_t a, b;
  int apex_a, apex_b;
};

// The corner of tet x that is not a vertex of tet y, when they share exactly a face; else -1.
int apex_off_shared_face(const UElement& x, const UElement& y) {
  int apex = -1, shared = 0;
  for (int i = 0; i < 4; ++i) {
    const bool in_y = x.v[i] == y.v[0] || x.v[i] == y.v[1] || x.v[i] == y.v[2] || x.v[i] == y.v[3];
    if (in_y)
      ++shared;
    else
      apex = i;
  }
  return shared == 3 ? apex : -1;
}

// For each of a leaf's tets, the others it shares exactly a face with, in increasing order (CSR:
// tet i's are list[offsets[i] .. offsets[i + 1])).
struct FacePartners {
  std::vector<uint32_t> offsets, list;
  std::span<const uint32_t> of(size_t i) const { return {list.data() + offsets[i], list.data() + offsets[i + 1]}; }
};

// Faces matched by their vertices in a small hash table (a sort of a leaf's 256 faces cost more
// than the rest of the leaf's encoding); a face of more than two tets, as a non-manifold mesh
// may have, gives every pair of them, each checked as apex_off_shared_face checks it (a
// repeated tet shares four vertices, not a face).
FacePartners face_partners(const UMesh& mesh, const std::vector<uint32_t>& tets) {
  struct Face {
    uint32_t v[3];
    uint32_t tet;
    int32_t next;  // the previous face of the same vertices, or -1
  };
  const size_t faces_count = 4 * tets.size();
  size_t slots = 16;
  while (slots < 2 * faces_count) slots *= 2;
  std::vector<int32_t> head(slots, -1);
  std::vector<Face> faces;
  faces.reserve(faces_count);
  std::vector<uint64_t> pairs;  // (i << 32 | j), both ways
  for (uint32_t i = 0; i < tets.size(); ++i) {
    const uint32_t* v = mesh.elements[tets[i]].v;
    for (int off = 0; off < 4; ++off) {
      Face f{{v[(off + 1) % 4], v[(off + 2) % 4], v[(off + 3) % 4]}, i, -1};
      std::sort(f.v, f.v + 3);
      size_t h = (f.v[0] * 0x9E3779B1u ^ f.v[1] * 0x85EBCA77u ^ f.v[2] * 0xC2B2AE3Du) & (slots - 1);
      while (head[h] >= 0 && !std::equal(f.v, f.v + 3, faces[size_t(head[h])].v)) h = (h + 1) & (slots - 1);
      for (int32_t k = head[h]; k >= 0; k = faces[size_t(k)].next) {
        const uint32_t j = faces[size_t(k)].tet;
        if (j != i && apex_off_shared_face(mesh.elements[tets[i]], mesh.elements[tets[j]]) >= 0)
          pairs.insert(pairs.end(), {uint64_t(i) << 32 | j, uint64_t(j) << 32 | i});
      }
      f.next = head[h];
      head[h] = int32_t(faces.size());
      faces.push_back(f);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  FacePartners p;
  p.offsets.assign(tets.size() + 1, 0);
  for (const uint64_t pair : pairs) {
    ++p.offsets[(pair >> 32) + 1];
    p.list.push_back(uint32_t(pair));
  }
  for (size_t i = 0; i < tets.size(); ++i) p.offsets[i + 1] += p.offsets[i];
  return p;
}

// Pairs the tets that share a face: repeatedly the unpaired tet with the fewest unpaired
// face neighbours with its neighbour of fewest (the greedy rule for matchings: tets with few
// options go first, so fewer are left single); the others stay single.
void pair_tets(const UMesh& mesh, const std::vector<uint32_t>& tets, std::vector<TetPair>& pairs,
               std::vector<uint32_t>& singles) {
  const size_t n = tets.size();
  const FacePartners partners = face_partners(mesh, tets);
  std::vector<uint8_t> used(n, 0);
  std::vector<uint32_t> options(n);  // each tet's unpaired partners, kept as tets are paired
  for (size_t i = 0; i < n; ++i) options[i] = partners.of(i).size();
  const auto take = [&](size_t i) {
    used[i] = 1;
    for (const uint32_t j : partners.of(i)) --options[j];
  };
  for (;;) {
    size_t best = n;
    uint32_t best_options = UINT32_MAX;
    for (size_t i = 0; i < n; ++i)
      if (!used[i] && options[i] > 0 && options[i] < best_options) best = i, best_options = options[i];
    if (best == n) break;
    size_t mate = n;
    uint32_t mate_options = UINT32_MAX;
    for (const uint32_t j : partners.of(best))
      if (!used[j] && options[j] < mate_options) mate = j, mate_options = options[j];
    const UElement &a = mesh.elements[tets[best]], &b = mesh.elements[tets[mate]];
    pairs.push_back({tets[best], tets[mate], apex_off_shared_face(a, b), apex_off_shared_face(b, a)});
    take(best);
    take(mate);
  }
  for (size_t i = 0; i < n; ++i)
    if (!used[i]) singles.push_back(tets[i]);
}

// The leaf's corners as reference vertices, in CompactLeaf's order: pairs (the shared face in
// the first tet's order, then each apex), single tets, pyramids, wedges, hexes.
std::vector<uint32_t> leaf_corners(const UMesh& mesh, const std::vector<TetPair>& pairs,
                                   const std::vector<uint32_t>& singles, const std::vector<uint32_t> (&by_type)[4]) {
  std::vector<uint32_t> corners;
  for (const TetPair& pair : pairs) {
    const UElement& a = mesh.elements[pair.a];
    for (int i = 0; i < 4; ++i)
      if (i != pair.apex_a) corners.push_back(a.v[i]);
    corners.push_back(a.v[pair.apex_a]);
    corners.push_back(mesh.elements[pair.b].v[pair.apex_b]);
  }
  for (const uint32_t e : singles) corners.insert(corners.end(), mesh.elements[e].v, mesh.elements[e].v + 4);
  for (int type = 1; type < 4; ++type)
    for (const uint32_t e : by_type[type]) {
      const UElement& el = mesh.elements[e];
      corners.insert(corners.end(), el.v, el.v + el.vertex_count());
    }
  return corners;
}

// Appends the leaf of elements [begin, end) of `order`: its vertex table (new sub-mesh vertices
// added to `local` and the vertex array) and its corners as bytes into the table.
void add_leaf(const UMesh& mesh, const std::vector<uint32_t>& order, size_t begin, size_t end,
              std::unordered_map<uint32_t, uint32_t>& local, CompactMesh& c) {
  std::vector<uint32_t> by_type[4];
  for (size_t k = begin; k < end; ++k) by_type[type_slot(mesh.elements[order[k]].vertex_count())].push_back(order[k]);
  std::vector<TetPair> pairs;
  std::vector<uint32_t> singles;
  pair_tets(mesh, by_type[0], pairs, singles);
  const std::vector<uint32_t> corners = leaf_corners(mesh, pairs, singles, by_type);
  std::vector<uint32_t> table;  // the leaf's distinct vertices, in first use
  std::vector<uint8_t> corner_bytes;
  for (const uint32_t v : corners) {
    const size_t at = size_t(std::find(table.begin(), table.end(), v) - table.begin());
    if (at == table.size()) table.push_back(v);
    corner_bytes.push_back(uint8_t(at));  // at most 256 distinct vertices: 64 tets, or 32 elements of up to 8
  }
  CompactLeaf leaf{};
  leaf.submesh = uint16_t(c.submeshes.size() - 1);
  leaf.first_byte = uint32_t(c.bytes.size() - c.submeshes.back().first_byte);
  leaf.table_last = uint8_t(table.size() - 1);
  for (int type = 0; type < 4; ++type) leaf.counts[type] = uint8_t(by_type[type].size());
  leaf.tet_pairs = uint8_t(pairs.size());
  const uint32_t base = c.submeshes.back().first_vertex;
  for (const uint32_t v : table) {
    auto [it, added] = local.try_emplace(v, uint32_t(c.vertices.size()) - base);
    if (added) {
      c.vertices.push_back(mesh.vertices[v]);
      c.source_vertex.push_back(v);
    }
    c.bytes.push_back(uint8_t(it->second & 0xff));
    c.bytes.push_back(uint8_t(it->second >> 8));
  }
  c.bytes.append(corner_bytes.data(), corner_bytes.data() + corner_bytes.size());
  c.paired_tets += 2 * pairs.size();
  c.leaves.push_back(leaf);
}

// Distinct vertices of elements [begin, end) not yet in `local`.
uint32_t new_vertices(const UMesh& mesh, const std::vector<uint32_t>& order, size_t begin, size_t end,
                      const std::unordered_map<uint32_t, uint32_t>& local) {
  std::vector<uint32_t> fresh;
  for (size_t k = begin; k < end; ++k) {
    const UElement& e = mesh.elements[order[k]];
    for (int i = 0; i < e.vertex_count(); ++i)
      if (!local.count(e.v[i])) fresh.push_back(e.v[i]);
  }
  std::sort(fresh.begin(), fresh.end());
  return uint32_t(std::unique(fresh.begin(), fresh.end()) - fresh.begin());
}

}  // namespace

namespace {
// The 8-wide tree bottom-up over consecutive groups; the root ends at index 0.
std::vector<CompactNode> build_nodes(const std::vector<box3f>& leaf_boxes) {
  std::vector<std::vector<CompactNode>> levels;
  std::vector<box3f> boxes = leaf_boxes;
  bool leaf_children = true;
  do {
    std::vector<CompactNode> level;
    std::vector<box3f> parents;
    for (size_t i = 0; i < boxes.size(); i += kCompactWidth) {
      const int count = int(std::min<size_t>(kCompactWidth, boxes.size() - i));
      box3f b;
      level.push_back(make_node(boxes.data() + i, count, uint32_t(i), leaf_children, b));
      parents.push_back(b);
    }
    levels.push_back(std::move(level));
    boxes = std::move(parents);
    leaf_children = false;
  } while (boxes.size() > 1);
  // Root first, then each level below: children indices shift by the nodes placed before them.
  std::vector<CompactNode> nodes;
  for (size_t l = levels.size(); l-- > 0;) {
    const uint32_t below = uint32_t(nodes.size() + levels[l].size());
    for (CompactNode node : levels[l]) {
      if (!node.leaf_children) node.first += below;
      nodes.push_back(node);
    }
  }
  return nodes;
}

}  // namespace

void build_compact_tree(CompactMesh& c, const std::vector<box3f>& leaf_boxes) {
  c.nodes = build_nodes(leaf_boxes);
  c.leaf_parents = uint32_t(c.nodes.size() - (leaf_boxes.size() + kCompactWidth - 1) / kCompactWidth);
}

bool all_tets(const UMesh& mesh, const std::vector<uint32_t>& order, size_t begin, size_t end) {
  for (size_t k = begin; k < end; ++k)
    if (mesh.elements[order[k]].vertex_count() != 4) return false;
  return true;
}

// Where the leaf starting at `begin` (a run's start) ends: after the two runs of one group (an
// even run and the next) where both hold tets alone, else after one run. 64 tets fit the table
// (256 corners); larger leaves of other types would fit it where they share vertices, but a
// search tests a leaf's elements one by one, and theirs need Newton iterations: with leaves of
// 64 the mixed mesh of bench/umesh_compact.py sampled at 0.48-0.50x the reference's speed
// instead of 0.57-0.61x.
size_t leaf_end(const UMesh& mesh, const std::vector<uint32_t>& order, size_t begin) {
  const size_t one = std::min(order.size(), begin + kClusterRun);
  const size_t two = std::min(order.size(), begin + 2 * kClusterRun);
  const bool pair_start = (begin / kClusterRun) % 2 == 0;
  return pair_start && two > one && all_tets(mesh, order, begin, two) ? two : one;
}

CompactMesh build_compact_mesh(const UMesh& mesh) {
  CompactMesh c;
  c.elements = mesh.elements.size();
  const std::vector<uint32_t> order = cluster_order(mesh);
  std::unordered_map<uint32_t, uint32_t> local;  // reference vertex -> local index in the current sub-mesh
  std::vector<box3f> leaf_boxes;
  for (size_t begin = 0, end = 0; begin < order.size(); begin = end) {
    end = leaf_end(mesh, order, begin);
    const uint32_t in_use = uint32_t(c.vertices.size()) - (c.submeshes.empty() ? 0 : c.submeshes.back().first_vertex);
    if (c.submeshes.empty() || in_use + new_vertices(mesh, order, begin, end, local) > 65536) {
      if (c.submeshes.size() > 0xffff)
        input_error("", "mesh too large for the compact encoding (over 65536 sub-meshes)");
      c.submeshes.push_back({uint32_t(c.vertices.size()), 0, c.bytes.size()});
      local.clear();
    }
    add_leaf(mesh, order, begin, end, local, c);
    box3f b = box3f::make_empty();
    for (size_t k = begin; k < end; ++k) b.extend(element_box(mesh.vertices.data(), mesh.elements[order[k]]));
    leaf_boxes.push_back(b);
  }
  build_compact_tree(c, leaf_boxes);
  c.replicated = c.vertices.size() - std::min<uint64_t>(c.vertices.size(), mesh.vertices.size());
  return c;
}

CompactBytes CompactMesh::bytes_by_part() const {
  CompactBytes b;
  b.vertices = vertices.size() * sizeof(vec3f);
  for (const CompactLeaf& leaf : leaves) b.tables += 2u * leaf.table_size();
  b.corners = bytes.size() - b.tables;
  b.leaves = leaves.size() * sizeof(CompactLeaf);
  b.nodes = nodes.size() * sizeof(CompactNode);
  b.submeshes = submeshes.size() * sizeof(CompactSubmesh);
  b.field = vertices.size() * sizeof(float);
  return b;
}

CompactMeshView compact_view(const CompactMesh& host, const CompactNode* nodes, const CompactLeaf* leaves,
                             const uint8_t* bytes, const CompactSubmesh* submeshes, const vec3f* vertices) {
  static std::atomic<uint64_t> views{0};
  CompactMeshView v;
  v.id = ++views;
  v.nodes = nodes, v.leaves = leaves, v.bytes = bytes, v.submeshes = submeshes, v.vertices = vertices;
  v.leaf_count = uint32_t(host.leaves.size());
  v.leaf_parents = host.leaf_parents;
  // Down the first children from the root: each level's first node.
  uint32_t first = 0;
  while (!host.nodes.empty()) {
    if (v.levels == CompactMeshView::kMaxLevels) input_error("", "compact mesh tree deeper than 16 levels");
    v.level_first[v.levels++] = first;
    if (host.nodes[first].leaf_children) break;
    first = host.nodes[first].first;
  }
  if (v.levels > 0 && v.level_first[v.levels - 1] != host.leaf_parents)
    input_error("", "compact mesh tree: its leaves' parents are not its last level");
  return v;
}

std::vector<float> CompactMesh::gather(const float* reference_values) const {
  std::vector<float> out(source_vertex.size());
  parallel_for("compact gather", int64_t(out.size()),
               [&](int64_t i) { out[size_t(i)] = reference_values[source_vertex[size_t(i)]]; });
  return out;
}

}  // namespace vs
