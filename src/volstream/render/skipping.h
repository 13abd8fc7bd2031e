// Empty-space skipping for any volume kind (volume/volume.h): a BVH template over the volume's
// region boxes, built once (binned SAH), then per step, transfer-function or iso change the
// regions are classified from their value ranges (classify.h) and the BVH refit (culled regions
// get empty boxes, accel/refit.h), never rebuilt. The ABRs use it; mesh macrocells, cells of a
// uniform grid, are walked over the grid instead (umesh/macrocells.h) and only classified here.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/accel/bvh.h"
#include "volstream/accel/bvh_wide.h"
#include "volstream/amr/model.h"
#include "volstream/backend/memory.h"
#include "volstream/render/integrators/settings.h"
#include "volstream/render/optics/transfer_function.h"

namespace vs {

struct SkipStats {
  uint64_t visible = 0;
  double classify_seconds = 0, refit_seconds = 0;
};

// Region i is visible when the transfer function gives some value of its range non-zero
// opacity, or its range contains one of the iso values. Empty ranges (no finite value) are not.
std::vector<uint8_t> classify_regions(const std::vector<Range>& ranges, const TransferTable& tf,
                                      const IntegratorSettings& iso);
// The flags a `refit` keeps: classify_regions with skip, none (keep all) without; one range per
// region expected. Times itself into stats->classify_seconds.
std::vector<uint8_t> regions_to_keep(const std::vector<Range>& ranges, size_t region_count, const TransferTable& tf,
                                     const IntegratorSettings& iso, bool skip, SkipStats* stats);

class RegionBvh {
 public:
  explicit RegionBvh(std::vector<box3f> region_boxes);  // builds the template
  // Takes a template built (or stored) over region_boxes already: a tree as build_bvh_sah makes.
  // wide_walk: also keep the refit tree's 4-wide form for the CPU walk (bvh_wide.h; the ABRs,
  // where traversal is a quarter of a render).
  RegionBvh(std::vector<box3f> region_boxes, Bvh template_bvh, bool wide_walk = false);
  // The same over a template that someone else keeps (a dataset's stored tree), for as long as
  // this lives.
  RegionBvh(std::vector<box3f> region_boxes, const Bvh* stored_template, bool wide_walk = false);
  // Classifies the regions and refits; skip = false keeps every region. Returns visible ones.
  uint64_t classify(const std::vector<Range>& ranges, const TransferTable& tf, const IntegratorSettings& iso, bool skip,
                    SkipStats* stats = nullptr);
  // Refits to the regions with keep[i] != 0 (empty: all). Returns the visible ones.
  uint64_t refit(const std::vector<uint8_t>& keep, SkipStats* stats = nullptr);
  const Bvh& template_bvh() const { return stored_template_ ? *stored_template_ : owned_template_; }
  const std::vector<BvhNode>& refit_nodes() const { return nodes_; }
  const Bvh4& wide_nodes() const { return wide_; }  // the refit tree's 4-wide form, or empty
  size_t region_count() const { return boxes_.size(); }

 private:
  void set_up(bool wide_walk);  // checks the template, copies it for refits, collapses

  std::vector<box3f> boxes_;
  Bvh owned_template_;                    // every region, never changes (when built here)
  const Bvh* stored_template_ = nullptr;  // or someone else's
  std::vector<BvhNode> nodes_;            // same topology, boxes refit to the visible regions
  Bvh4 wide_;                             // nodes_ collapsed to 4-wide nodes (wide_walk), refit with them
  CountedBytes bytes_;                    // template, refit copy and boxes (host)
};

}  // namespace vs
