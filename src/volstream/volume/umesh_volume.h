// An unstructured mesh (umesh/umesh.h, reference encoding; umesh/compact.h, compact) as a volume: the regions are the
// non-empty macrocells (umesh/macrocells.h), found front to back by a walk over their grid that
// skips empty and culled cells; a sample locates its element through the element BVH (umesh/element_bvh.h) wherever it
// is, so sample and sample_near are the same, and a point in no element (a hole, a notch, the
// space between the parts of a mesh inside a macrocell) is NaN, which the integrator skips.
#pragma once
#include <cmath>
#include <cstdint>

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

  VS_HOST_DEVICE float sample(int field, uint32_t, const vec3f& p) const { return mesh.sample(fields[field], p); }
  VS_HOST_DEVICE float sample_near(int field, uint32_t, const vec3f& p) const { return mesh.sample(fields[field], p); }
  // With the ray's hint (integrator.h): the element of the ray's previous sample is tried first.
  using Hint = typename Locator::Hint;
  VS_HOST_DEVICE float sample(int field, uint32_t, const vec3f& p, Hint& hint) const {
    return mesh.sample(fields[field], p, hint);
  }
  VS_HOST_DEVICE float sample_near(int field, uint32_t, const vec3f& p, Hint& hint) const {
    return mesh.sample(fields[field], p, hint);
  }
  VS_HOST_DEVICE float step_width(uint32_t region) const { return step_widths[region]; }
  VS_HOST_DEVICE int64_t locate(const vec3f& p) const {
    if (!grid.bounds.contains(p)) return -1;
    return region_of_cell[grid.index(grid.cell_of(p))];
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
