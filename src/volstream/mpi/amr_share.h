// A data-parallel rank's share of an AMR dataset (mpi/partition.h, rank_share), read from the
// files: a dataset opened with its ABRs deferred (io/dataset.h, TopologyLoad::deferred) reads
// only the ABR chunks (amr/abrs.h, AbrChunk) that may hold an ABR of the share, chosen by the
// same margin rule over the chunks' boxes and widths (held_regions; a chunk's box holds its ABRs
// and its width is their largest, so the chunks chosen hold every ABR chosen), and then chooses
// the ABRs among those: the share is the one made from the whole topology.
#pragma once
#include "volstream/io/dataset.h"
#include "volstream/mpi/partition.h"

namespace vs {

// The share of `region` (global ABR indices); reads the chunks it needs when the ABRs are deferred.
RankShare read_rank_share(Dataset& dataset, const Box3<double>& region, const IntegratorSettings& settings);

}  // namespace vs
