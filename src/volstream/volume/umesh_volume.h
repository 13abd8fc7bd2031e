// An unstructured mesh (umesh/umesh.h, reference encoding; umesh/compact.h, compact) as a volume: the regions are the
// non-empty macrocells (umesh/macrocells.h), found front to back by a walk over their grid that
// skips empty and culled cells; a sample locates its element through the element BVH (umesh/element_bvh.h) wherever it
// is, so sample and sample_near are the same, and a point in no element (a hole, a notch, the
// space between the parts of a mesh inside a macrocell) is NaN, which the integrator skips.
#pragma once
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "volstream/umesh/compact.h"
#include "volstream/umesh/element_bvh.h"
#include "volstream/umesh/macrocells.h"
#include "volstream/volume/volume.h"

namespace vs {

// Locator: how points find their element and value (UMeshView for the reference encoding,
// CompactMeshView for paper 002's compact one): sample(values, p) and sample(values, p, hint).
template <typename Locator>
struct MeshVolume {
  Locator mesh;
  const float* fields[kVolumeFields] = {};  // per vertex; fields[1] may be null
  const uint8_t* visible = nullptr;         // per macrocell: 0 where classification culled it
  const float* step_widths = nullptr;       // per macrocell
  MacroGrid grid;
  const int32_t* region_of_cell = nullptr;
  // The block of grid cells that holds every visible macrocell (UMeshRenderer::refit; lo > hi on
  // an axis: none): rays walk only its cells. The default is the whole grid.
  vec3i shown_lo{0, 0, 0}, shown_hi{INT32_MAX, INT32_MAX, INT32_MAX};
  // Per macrocell, the element where the walk of a ray's first sample in it starts
  // (start_walk; the reference encoding on the CPU, null elsewhere): kWalkStartUnknown until a
  // ray needs it, kNoWalkStart where the cell's centre lies in no element.
  uint32_t* walk_starts = nullptr;
  static constexpr uint32_t kWalkStartUnknown = 0xffffffffu, kNoWalkStart = 0xfffffffeu;

  VS_HOST_DEVICE float sample(int field, uint32_t, const vec3f& p) const { return mesh.sample(fields[field], p); }
  VS_HOST_DEVICE float sample_near(int field, uint32_t, const vec3f& p) const { return mesh.sample(fields[field], p); }
  // With the ray's hint (integrator.h): the element of the ray's previous sample is tried first.
  using Hint = typename Locator::Hint;
  VS_FORCE_INLINE VS_HOST_DEVICE float sample(int field, uint32_t, const vec3f& p, Hint& hint) const {
#if !defined(__CUDA_ARCH__)
    if constexpr (std::is_same_v<Locator, UMeshView>)
      if (hint.element < 0 && walk_starts && !hint.in_hole) start_walk(p, hint);
#endif
    return mesh.sample(fields[field], p, hint);
  }
  VS_HOST_DEVICE float sample_near(int field, uint32_t region, const vec3f& p, Hint& hint) const {
    return sample(field, region, p, hint);
  }
#if !defined(__CUDA_ARCH__)
  // A ray's first sample walks from its macrocell's start element instead of searching the
  // element BVH from the root (3,100 instructions a search on a 1M-tet mesh, one per ray: 8% of
  // a haze render's). The start is the element holding the cell's centre, found by the first
  // ray that needs it; it depends on the cell alone, so an image does not depend on which
  // thread found it. From there the walk ends in an element that holds p strictly, or the BVH
  // search decides as it did from the root.
  __attribute__((noinline)) void start_walk(const vec3f& p, Hint& hint) const {  // once a ray: out of line
    vec3i cell;
    const int64_t region = locate(p, cell);
    if (region < 0) return;
    uint32_t* slot = walk_starts + region;
    uint32_t start = __atomic_load_n(slot, __ATOMIC_RELAXED);
    if (start == kWalkStartUnknown) {  // threads that race here find the same element
      const int64_t e = mesh.locate(grid.cell_box(cell).center()).element;
      start = e >= 0 ? uint32_t(e) : kNoWalkStart;
      __atomic_store_n(slot, start, __ATOMIC_RELAXED);
    }
    if (start != kNoWalkStart) hint.element = start;
  }
#endif
  VS_HOST_DEVICE float step_width(uint32_t region) const { return step_widths[region]; }
  VS_HOST_DEVICE int64_t locate(const vec3f& p) const {
    vec3i cell;
    return locate(p, cell);
  }
  // The same, and p's grid cell where p is inside the grid.
  VS_HOST_DEVICE int64_t locate(const vec3f& p, vec3i& cell) const {
    if (!grid.bounds.contains(p)) return -1;
    cell = grid.cell_of(p);
    return region_of_cell[grid.index(cell)];
  }
  // Consecutive visible macrocells of one step width make one interval, in the walk over the
  // block of cells that holds them all (a blobs look's rays skip the culled rest of the grid). A ray enters a macrocell
  // every two or three samples, and each interval costs its own set-up; on the lattice that mesh
  // frames march (settings.h, March::lattice) the merged interval has the same samples as its
  // cells, and the widths are on a ladder (MacroCells::step_width), so that neighbours mostly
  // share one. Culled and empty cells still end an interval.
  template <typename Visit>
  VS_HOST_DEVICE void for_each_interval(const vec3f& org, const vec3f& dir, Visit&& visit) const {
    RayInterval run{0u, 0.f, 0.f};
    bool open = false;  // run holds cells not yet handed over
    for_each_cell_along(grid, shown_lo, shown_hi, org, dir, [&](uint64_t cell, float t0, float t1) {
      const int32_t region = region_of_cell[cell];
      const bool shown = region >= 0 && visible[region];
      if (shown && open && step_widths[region] == step_widths[run.region]) {  // the walk's next cell
        run.t1 = t1;
        return true;
      }
      if (open && !visit(run)) {
        open = false;  // the ray is finished: nothing is left to hand over
        return false;
      }
      open = shown;
      if (shown) run = {uint32_t(region), t0, t1};
      return true;
    });
    if (open) visit(run);
  }
};
using UMeshVolume = MeshVolume<UMeshView>;
using CompactMeshVolume = MeshVolume<CompactMeshView>;
static_assert(Volume<UMeshVolume>);
static_assert(Volume<CompactMeshVolume>);

}  // namespace vs
