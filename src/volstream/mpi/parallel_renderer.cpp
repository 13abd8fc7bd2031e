#include "volstream/mpi/parallel_renderer.h"

#include "volstream/frame/look.h"
#include "volstream/mpi/amr_share.h"
#include "volstream/mpi/mesh_share.h"

namespace vs::mpi {

void check_parallel_request(const FrameRequest& request) {
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
  check_parallel_request(request);
  DatasetPart part;
  part.world_bounds = world_bounds(dataset);
  if (dataset.is_mesh())
    share_mesh(part, request.integrator, rank, ranks);
  else
    share_bricks(part, request.integrator, rank, ranks);
  const bool empty = part.abrs.empty() && part.mesh_items.empty();
  dataset.restrict_to(std::move(part));
  if (dataset.is_mesh()) share_.vertices = dataset.mesh_vertices().size();
  share_.topology_bytes = dataset.topology_bytes();
  share_.topology_bytes_read = dataset.topology_bytes_read();
  if (!empty) renderer_ = std::make_unique<FrameRenderer>(dataset, device);
}

void ParallelRenderer::share_bricks(DatasetPart& part, const IntegratorSettings& settings, int rank, int ranks) {
  const AmrTopology& topology = dataset_.topology();  // every brick (deferred: no ABRs yet)
  partition_ = partition_bricks(topology.bricks, ranks);
  part.owned = partition_.regions[size_t(rank)];
  RankShare mine = read_rank_share(dataset_, part.owned, settings);
  share_.ghost_margin = mine.margin;
  for (const Brick& b : topology.bricks) part.owned_cells += cells_in(b, part.owned);
  for (uint32_t b : mine.bricks) share_.held += uint64_t(topology.bricks[b].cell_count());
  share_.owned = part.owned_cells;
  share_.bricks = mine.bricks.size();
  share_.abrs = mine.abrs.size();
  part.bricks = std::move(mine.bricks);
  part.abrs = std::move(mine.abrs);
}

// The partition of the mesh's index items by their points, weighted by their elements, and this
// rank's share; the part is rendered on the whole mesh's macrocell grid.
void ParallelRenderer::share_mesh(DatasetPart& part, const IntegratorSettings& settings, int rank, int ranks) {
  const MeshIndex index = dataset_.mesh_index();
  const std::vector<vec3d> points = index.item_points();
  partition_ = partition_points(points, ranks, index.item_elements);
  part.owned = partition_.regions[size_t(rank)];
  part.mesh_grid = index.cells.grid;
  MeshShare mine = mesh_share(index, points, part.owned, settings);
  share_.mesh = true;
  share_.ghost_margin = mine.margin;
  share_.owned = mine.owned_elements;
  share_.held = mine.held_elements;
  share_.items = mine.items.size();
  part.mesh_items = std::move(mine.items);
}

ParallelRenderer::~ParallelRenderer() = default;

Image ParallelRenderer::render_local(const FrameRequest& request, FrameReport* report) {
  check_parallel_request(request);
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
