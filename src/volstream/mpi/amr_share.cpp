#include "volstream/mpi/amr_share.h"

namespace vs {

namespace {
// The chunks that may hold an ABR of the share: each ABR's margin test passes for its chunk too,
// whose box holds the ABR's and whose width (hence margin) is at least the ABR's.
std::vector<uint32_t> held_chunks(const std::vector<AbrChunk>& chunks, const Box3<double>& region,
                                  const IntegratorSettings& settings) {
  std::vector<RegionExtent> extents;
  extents.reserve(chunks.size());
  for (const AbrChunk& c : chunks) extents.push_back({c.box, c.finest_width});
  return held_regions(extents, region, settings).indices;
}
}  // namespace

RankShare read_rank_share(Dataset& dataset, const Box3<double>& region, const IntegratorSettings& settings) {
  if (dataset.topology_deferred()) dataset.read_abr_chunks(held_chunks(dataset.abr_chunks(), region, settings));
  RankShare share = rank_share(dataset.topology(), region, settings);
  for (uint32_t& a : share.abrs) a = dataset.abr_id(a);
  return share;
}

}  // namespace vs
