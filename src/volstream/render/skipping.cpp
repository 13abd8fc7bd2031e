#include "volstream/render/skipping.h"

#include <algorithm>
#include <stdexcept>

#include "volstream/accel/bvh_sah.h"
#include "volstream/accel/refit.h"
#include "volstream/backend/parallel.h"
#include "volstream/core/stopwatch.h"
#include "volstream/render/classify.h"

namespace vs {

std::vector<uint8_t> classify_regions(const std::vector<Range>& ranges, const TransferTable& tf,
                                      const IntegratorSettings& iso) {
  std::vector<uint8_t> visible(ranges.size());
  const OpacityIndex opacity = tf.opacity_index();
  parallel_for("classify", int64_t(ranges.size()),
               [&](int64_t i) { visible[size_t(i)] = abr_visible(ranges[size_t(i)], opacity, iso) ? 1 : 0; });
  return visible;
}

std::vector<uint8_t> regions_to_keep(const std::vector<Range>& ranges, size_t region_count, const TransferTable& tf,
                                     const IntegratorSettings& iso, bool skip, SkipStats* stats) {
  if (ranges.size() != region_count) throw std::invalid_argument("one value range per region expected");
  Stopwatch watch;
  std::vector<uint8_t> keep = skip ? classify_regions(ranges, tf, iso) : std::vector<uint8_t>{};
  if (stats) stats->classify_seconds = watch.seconds();
  return keep;
}

RegionBvh::RegionBvh(std::vector<box3f> region_boxes) : RegionBvh(region_boxes, build_bvh_sah(region_boxes)) {}

RegionBvh::RegionBvh(std::vector<box3f> region_boxes, Bvh template_bvh, bool wide_walk)
    : boxes_(std::move(region_boxes)), owned_template_(std::move(template_bvh)) {
  set_up(wide_walk);
}

RegionBvh::RegionBvh(std::vector<box3f> region_boxes, const Bvh* stored_template, bool wide_walk)
    : boxes_(std::move(region_boxes)), stored_template_(stored_template) {
  set_up(wide_walk);
}

void RegionBvh::set_up(bool wide_walk) {
  // Built by build_bvh_sah or read and checked (bvh_tree_problem) by the dataset reader.
  const std::vector<BvhNode>& all = template_bvh().nodes;
  if (all.size() != (boxes_.empty() ? 0 : 2 * boxes_.size() - 1))
    throw std::logic_error("region BVH: not a tree over the regions");
  nodes_ = all;
  if (wide_walk) wide_ = collapse_to_bvh4(nodes_);
  // The template counts here also when stored: the dataset's topology bytes leave it out.
  bytes_ = CountedBytes("BVH", MemorySpace::host,
                        int64_t((all.size() + nodes_.size()) * sizeof(BvhNode) + boxes_.size() * sizeof(box3f) +
                                wide_.nodes.size() * sizeof(Bvh4Node) + wide_.source.size() * sizeof(uint32_t)));
}

uint64_t RegionBvh::classify(const std::vector<Range>& ranges, const TransferTable& tf, const IntegratorSettings& iso,
                             bool skip, SkipStats* stats) {
  return refit(regions_to_keep(ranges, boxes_.size(), tf, iso, skip, stats), stats);
}

uint64_t RegionBvh::refit(const std::vector<uint8_t>& keep, SkipStats* stats) {
  Stopwatch watch;
  refit_bvh(nodes_, boxes_, keep);
  if (!wide_.nodes.empty()) refit_bvh4(wide_, nodes_);  // only where the CPU walk uses it (ABRs)
  const uint64_t visible = keep.empty() ? boxes_.size() : uint64_t(std::count(keep.begin(), keep.end(), uint8_t(1)));
  if (stats) {
    stats->refit_seconds = watch.seconds();
    stats->visible = visible;
  }
  return visible;
}

}  // namespace vs
