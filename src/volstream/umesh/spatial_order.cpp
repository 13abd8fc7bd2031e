#include "volstream/umesh/spatial_order.h"

#include <algorithm>
#include <numeric>

#include <tbb/parallel_sort.h>

namespace vs {
namespace {

// The bits of x (21 of them) spread to every third bit.
uint64_t spread_bits(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

uint64_t morton_code(const vec3f& p, const box3f& bounds) {
  constexpr float kCells = float((1 << 21) - 1);
  const vec3f size = bounds.size();
  uint64_t code = 0;
  for (int a = 0; a < 3; ++a) {
    const float u = size[a] > 0.f ? (p[a] - bounds.lower[a]) / size[a] : 0.f;
    code |= spread_bits(uint64_t(std::clamp(u, 0.f, 1.f) * kCells)) << a;
  }
  return code;
}

}  // namespace

MeshOrder spatial_order(const UMesh& mesh) {
  const size_t elements = mesh.elements.size();
  box3f bounds = box3f::make_empty();
  for (const vec3f& v : mesh.vertices) bounds.extend(v);
  std::vector<std::pair<uint64_t, uint32_t>> keyed(elements);
  for (size_t e = 0; e < elements; ++e)
    keyed[e] = {morton_code(element_box(mesh.vertices.data(), mesh.elements[e]).center(), bounds), uint32_t(e)};
  tbb::parallel_sort(keyed.begin(), keyed.end());  // ties by input index: deterministic

  MeshOrder order;
  order.element_source.resize(elements);
  order.vertex_target.assign(mesh.vertices.size(), kNoVertex);
  uint32_t next = 0;
  for (size_t i = 0; i < elements; ++i) {
    const uint32_t e = keyed[i].second;
    order.element_source[i] = e;
    const UElement& el = mesh.elements[e];
    for (int k = 0; k < el.vertex_count(); ++k)
      if (order.vertex_target[el.v[k]] == kNoVertex) order.vertex_target[el.v[k]] = next++;
  }
  // Vertices no element uses keep their values (a step's range covers every vertex), last.
  for (uint32_t& target : order.vertex_target)
    if (target == kNoVertex) target = next++;
  return order;
}

UMesh reordered(const UMesh& mesh, const MeshOrder& order) {
  UMesh out;
  out.vertices.resize(mesh.vertices.size());
  for (size_t v = 0; v < mesh.vertices.size(); ++v) out.vertices[order.vertex_target[v]] = mesh.vertices[v];
  out.elements.resize(mesh.elements.size());
  for (size_t i = 0; i < mesh.elements.size(); ++i) {
    UElement el = mesh.elements[order.element_source[i]];
    for (uint32_t& v : el.v)
      if (v != kNoVertex) v = order.vertex_target[v];
    out.elements[i] = el;
  }
  std::copy(std::begin(mesh.count_by_type), std::end(mesh.count_by_type), std::begin(out.count_by_type));
  return out;
}

std::vector<float> reordered_values(const std::vector<float>& values, const MeshOrder& order) {
  std::vector<float> out(values.size());
  for (size_t v = 0; v < values.size(); ++v) out[order.vertex_target[v]] = values[v];
  return out;
}

}  // namespace vs
