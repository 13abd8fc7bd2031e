// One rank of a data-parallel frame (issue 17; docs/ARCHITECTURE.md "Data-parallel rendering").
// Every rank computes the same kd partition from the topology (no messages), keeps only its
// share of the dataset (its ABRs and bricks, or mesh elements, owned and ghost; mpi/partition.h,
// mpi/mesh_share.h, Dataset::restrict_to), renders the
// light from its own region with the usual FrameRenderer, and the ranks composite their partial
// images in the kd-tree's visibility order (mpi/comm.h).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "volstream/frame/frame_renderer.h"
#include "volstream/mpi/comm.h"
#include "volstream/mpi/partition.h"

namespace vs::mpi {

// What this rank holds and read.
struct ShareStats {
  bool mesh = false;
  uint64_t owned = 0;                // cells (AMR) or elements (meshes: by centroid) in its region
  uint64_t held = 0;                 // cells of the bricks it holds, or elements it holds (owned + ghosts)
  uint64_t bricks = 0, abrs = 0;     // AMR
  uint64_t vertices = 0, items = 0;  // meshes: vertices (compact: local ones) and elements or leaves
  uint64_t topology_bytes = 0;       // host bytes of the share's topology (Dataset::topology_bytes)
  uint64_t topology_bytes_read = 0;  // bytes of topology files read (Dataset::topology_bytes_read)
  double ghost_margin = 0;           // grid units
};

class ParallelRenderer {
 public:
  // Partitions the dataset among `ranks` and restricts it to `rank`'s share. UsageError for what
  // cannot be split yet (the block integrator, blackbody optics, several rays a pixel).
  ParallelRenderer(Dataset& dataset, Device device, const FrameRequest& request, int rank, int ranks);
  ~ParallelRenderer();

  // This rank's partial image: premultiplied light from its region only (not collective).
  Image render_local(const FrameRequest& request, FrameReport* report = nullptr);
  // Collective: the frame on rank 0 (empty elsewhere).
  Image composite(const Image& partial, const FrameRequest& request, CompositeScheme scheme,
                  CompositeStats* stats = nullptr) const;

  const Partition& partition() const { return partition_; }
  const ShareStats& share() const { return share_; }

 private:
  void share_bricks(DatasetPart& part, const IntegratorSettings& settings, int rank, int ranks);
  void share_mesh(DatasetPart& part, const IntegratorSettings& settings, int rank, int ranks);
  Dataset& dataset_;
  Partition partition_;
  ShareStats share_;
  std::unique_ptr<FrameRenderer> renderer_;  // null when the share is empty
};

// The request's checks for a data-parallel frame (UsageError naming what is not supported).
void check_parallel_request(const FrameRequest& request);

}  // namespace vs::mpi
