// Data-parallel partition of a dataset (issue 17): a kd-tree that cuts the data at the plane that
// balances the estimated render cost between the two sides in proportion to their rank counts.
// AMR: over the bricks' cells, split on faces of the coarsest cells (so every cell lies wholly in
// one region). Meshes: over the elements' centroids, one unit each, split between neighbouring
// centroids (so every element is owned by the one region holding its centroid).
// Each rank owns one leaf: a convex box (half-open, unbounded at the outer faces, so the boxes
// tile all of space). The tree gives the visibility order of the boxes for any view.
//
// A rank renders only light from points in its box (integrator.h, FrameView::owned) but needs
// the field a little beyond it: the integrator looks one step back for isosurface crossings and
// half a cell aside for gradients. So it holds every ABR (with all its bricks) that reaches its
// box grown by that margin; the bricks it holds beyond its own cells are its ghost bricks. A mesh
// rank likewise holds every macrocell (the mesh's regions) within that margin, with every element
// overlapping one (mpi/mesh_share.h).
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/amr/model.h"
#include "volstream/render/integrators/settings.h"

namespace vs {

struct PartitionNode {
  int axis = -1;  // -1: a leaf (one rank)
  double plane = 0;
  int left = -1, right = -1;
  int first_rank = 0, rank_count = 1;  // the leaves below, in rank order
};

struct Partition {
  std::vector<PartitionNode> nodes;   // nodes[0] is the root
  std::vector<Box3<double>> regions;  // per rank, grid units, half-open [lower, upper)
  // Ranks front to back for a view: from the eye (perspective) or along dir (orthographic),
  // both in grid units.
  std::vector<int> visibility_order(const vec3d& eye, const vec3d& dir, bool ortho) const;
};

// What a kd split balances: the data's bounds, the cost of the data in a region, and the planes
// along an axis at which a region may be cut (ascending, inside the data).
class SplitCost {
 public:
  virtual ~SplitCost() = default;
  virtual Box3<double> data_bounds() const = 0;
  virtual double cost(const Box3<double>& region) const = 0;
  virtual std::vector<double> planes(const Box3<double>& region, int axis) const = 0;
};
Partition partition_by_cost(const SplitCost& model, int ranks);

// Splits the bricks' cells among `ranks` regions (ranks >= 1).
Partition partition_bricks(const std::vector<Brick>& bricks, int ranks);
// Splits points (a mesh's element centroids, or compact leaves' points, grid units) among `ranks`
// regions, equal counts (sums of `weights`, one per point; empty: one each) as far as distinct
// coordinates allow.
Partition partition_points(const std::vector<vec3d>& points, int ranks, const std::vector<uint32_t>& weights = {});
// p lies in the half-open region.
bool in_region(const Box3<double>& region, const vec3d& p);

// The estimated render cost of a cell of width w when the coarsest is w_max: one unit for its
// memory and reading, plus (w / w_max)^2 for the rays that cross it (a cell's share of the image
// grows with its area; the samples per ray in it stay `rate`).
double cell_cost(int32_t level, int32_t max_level);

// Cells of `b` whose lower corner lies in the half-open `region` (a whole cell, as regions are
// split on coarse cell faces).
uint64_t cells_in(const Brick& b, const Box3<double>& region);

// What one rank holds: the ABRs it may sample (global indices, ascending) and the bricks they use.
// The integrator samples whole ABR intervals, so a rank holds every ABR that meets its region,
// and near it the ABRs its composited light depends on: the sample before an owned one (at most
// one step of either ABR back: the largest step among the ABRs in the region, or the ABR's
// own) and gradient stencils (half a finest cell of the region's ABRs). `margin` reports the
// region's part of that reach (grid units). Closed tests, 5 % to spare.
// The regions a rank samples, of any volume (ABRs, mesh macrocells: boxes and finest widths),
// by the rule above: indices ascending, and the margin.
struct RegionExtent {
  box3f box;
  float width;
};
struct HeldRegions {
  std::vector<uint32_t> indices;
  double margin = 0;
};
HeldRegions held_regions(const std::vector<RegionExtent>& regions, const Box3<double>& region,
                         const IntegratorSettings& settings);

struct RankShare {
  std::vector<uint32_t> abrs, bricks;
  double margin = 0;
};
RankShare rank_share(const AmrTopology& topology, const Box3<double>& region, const IntegratorSettings& settings);

}  // namespace vs
