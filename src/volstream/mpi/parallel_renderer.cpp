#include "volstream/mpi/parallel_renderer.h"

#include "volstream/frame/look.h"

namespace vs::mpi {

void check_parallel_request(const Dataset& dataset, const FrameRequest& request) {
  if (dataset.is_mesh())
    throw UsageError("unstructured meshes cannot be split among MPI ranks yet (run without mpirun)");
  if (request.kind != IntegratorKind::abr)
    throw UsageError("under mpirun only the abr integrator splits the data (use --integrator abr)");
  // Blackbody light is absorbed per channel; the composited images carry one opacity.
  if (request.optics != OpticsKind::tf) throw UsageError("under mpirun only the tf optics is supported");
  // A pixel's rays are averaged inside a rank; the average of "over"s is not the "over" of the
  // averages, so each ray would need its own compositing.
  if (request.integrator.spp > 1) throw UsageError("under mpirun --spp must be 1 for now");
}

ParallelRenderer::ParallelRenderer(Dataset& dataset, Device device, const FrameRequest& request, int rank, int ranks)
    : dataset_(dataset) {
  check_parallel_request(dataset, request);
  const AmrTopology& topology = dataset.topology();
  partition_ = partition_bricks(topology.bricks, ranks);
  DatasetPart part;
  part.owned = partition_.regions[size_t(rank)];
  part.world_bounds = world_bounds(dataset);
  RankShare mine = rank_share(topology, part.owned, request.integrator);
  share_.ghost_margin = mine.margin;
  for (const Brick& b : topology.bricks) part.owned_cells += cells_in(b, part.owned);
  for (uint32_t b : mine.bricks) share_.held_cells += uint64_t(topology.bricks[b].cell_count());
  share_.owned_cells = part.owned_cells;
  share_.bricks = mine.bricks.size();
  share_.abrs = mine.abrs.size();
  part.bricks = std::move(mine.bricks);
  part.abrs = std::move(mine.abrs);
  const bool empty = part.abrs.empty();
  dataset.restrict_to(std::move(part));
  if (!empty) renderer_ = std::make_unique<FrameRenderer>(dataset, device);
}

ParallelRenderer::~ParallelRenderer() = default;

Image ParallelRenderer::render_local(const FrameRequest& request, FrameReport* report) {
  check_parallel_request(dataset_, request);
  if (!renderer_) {  // nothing here: transparent
    if (report) *report = {};
    return Image(request.width, request.height);
  }
  return renderer_->render(request, report);
}

Image ParallelRenderer::composite(const Image& partial, const FrameRequest& request, CompositeScheme scheme,
                                  CompositeStats* stats) const {
  const WorldTransform& t = dataset_.manifest().transform;
  const Camera& c = request.camera;
  const vec3d eye = t.to_grid(c.position);
  const vec3d dir = (c.look_at - c.position) / t.cell_size;
  return mpi::composite(partial, partition_.visibility_order(eye, dir, c.ortho), scheme, stats);
}

}  // namespace vs::mpi
