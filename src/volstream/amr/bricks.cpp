// Brick builder. Cells are grouped by level; each level's cells are split recursively, kd-tree
// style, until every node is a dense box (a brick). Splits prefer empty slabs (gaps between
// clusters), then the plane where the number of cells per slab changes most (the edge of a
// refinement region), so bricks follow the shape of the refinement. Nodes are contiguous ranges
// of one array that is partitioned in place, so the final array is already in device order.
#include "volstream/amr/bricks.h"

#include <tbb/parallel_sort.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <mutex>

#include "volstream/core/error.h"

namespace vs {
namespace {

// A cell during the build: position in the level's own index space (lower >> level) and where it
// came from. The level is implicit (one level is built at a time).
struct BuildCell {
  vec3i pos;
  uint32_t input;
};

struct Split {
  int axis = -1;
  int32_t plane = 0;  // cells with pos[axis] < plane go left
};

class LevelBuilder {
 public:
  LevelBuilder(BuildCell* cells, int32_t level, const BrickBuildOptions& opt, const std::string& source)
      : cells_(cells), level_(level), opt_(opt), source_(source) {}

  void build(uint64_t begin, uint64_t end) {
    tbb::task_group tasks;
    build_node(begin, end, tasks);
    tasks.wait();
  }

  std::vector<Brick> take_bricks() { return std::move(bricks_); }

 private:
  static constexpr uint64_t kParallelThreshold = 1 << 15;

  void build_node(uint64_t begin, uint64_t end, tbb::task_group& tasks) {
    box3i box = bounds(begin, end);
    const vec3i dims = box.upper - box.lower + vec3i(1);
    const uint64_t count = end - begin;
    // Saturate instead of overflowing: coordinates may span 2^29 cells per axis.
    const uint64_t volume = std::min<uint64_t>(uint64_t(dims.x) * uint64_t(dims.y), count + 1) * uint64_t(dims.z);
    if (count > volume) input_error(source_, "two cells at the same position (level " + std::to_string(level_) + ")");
    Split split;
    if (count == volume) {
      if (reduce_max(dims) <= opt_.max_brick_dim) return emit_brick(begin, end, box);
      split.axis = dims.x >= dims.y && dims.x >= dims.z ? 0 : (dims.y >= dims.z ? 1 : 2);
      split.plane = box.lower[split.axis] + dims[split.axis] / 2;
    } else {
      split = choose_split(begin, end, box);
    }
    const int axis = split.axis;
    const int32_t plane = split.plane;
    BuildCell* mid =
        std::partition(cells_ + begin, cells_ + end, [&](const BuildCell& c) { return c.pos[axis] < plane; });
    const uint64_t m = uint64_t(mid - cells_);
    if (count >= kParallelThreshold) {
      tasks.run([this, begin, m, &tasks] { build_node(begin, m, tasks); });
      build_node(m, end, tasks);
    } else {
      build_node(begin, m, tasks);
      build_node(m, end, tasks);
    }
  }

  box3i bounds(uint64_t begin, uint64_t end) const {
    box3i b = box3i::make_empty();
    for (uint64_t i = begin; i < end; ++i) b.extend(cells_[i].pos);
    return b;
  }

  Split choose_split(uint64_t begin, uint64_t end, const box3i& box) {
    const vec3i dims = box.upper - box.lower + vec3i(1);
    const uint64_t count = end - begin;
    Split best;
    double best_score = -1;
    for (int axis = 0; axis < 3; ++axis) {
      if (dims[axis] < 2) continue;
      if (uint64_t(dims[axis]) > 8 * count + 1024) {
        // Very sparse: a histogram would be larger than the node; split at the median.
        return median_split(begin, end, box, axis);
      }
      std::vector<uint32_t> hist(size_t(dims[axis]), 0);
      for (uint64_t i = begin; i < end; ++i) ++hist[size_t(cells_[i].pos[axis] - box.lower[axis])];
      score_axis(hist, axis, box.lower[axis], best, best_score);
    }
    if (best.axis < 0) {  // all slabs equal and no gap: split the longest axis in the middle
      best.axis = dims.x >= dims.y && dims.x >= dims.z ? 0 : (dims.y >= dims.z ? 1 : 2);
      best.plane = box.lower[best.axis] + dims[best.axis] / 2;
    }
    return best;
  }

  // Scores every plane of one axis. An empty slab beats any other split (score above any count
  // jump); among equals, the plane nearest the middle wins so the tree stays balanced.
  static void score_axis(const std::vector<uint32_t>& hist, int axis, int32_t lower, Split& best, double& best_score) {
    const size_t n = hist.size();
    const double big = 4.0 * double(*std::max_element(hist.begin(), hist.end())) + 4.0;
    for (size_t i = 1; i < n; ++i) {
      double score;
      if (hist[i] == 0 || hist[i - 1] == 0) {
        if (hist[i] == 0 && hist[i - 1] == 0) continue;  // inside a gap: cut at its edges
        score = big;
      } else {
        score = std::abs(double(hist[i]) - double(hist[i - 1]));
        if (score == 0) continue;
      }
      const double centred = 1.0 - std::abs(double(i) / double(n) - 0.5);  // 0.5 .. 1
      score = score + centred * 1e-3 * big;                                // tie-break towards the middle
      if (score > best_score) {
        best_score = score;
        best = {axis, lower + int32_t(i)};
      }
    }
  }

  Split median_split(uint64_t begin, uint64_t end, const box3i& box, int axis) {
    const uint64_t mid = begin + (end - begin) / 2;
    std::nth_element(cells_ + begin, cells_ + mid, cells_ + end,
                     [axis](const BuildCell& a, const BuildCell& b) { return a.pos[axis] < b.pos[axis]; });
    int32_t plane = cells_[mid].pos[axis];
    if (plane == box.lower[axis]) plane += 1;  // never an empty side
    return {axis, plane};
  }

  // Sorts the node's cells into brick order (x fastest) and records the brick.
  void emit_brick(uint64_t begin, uint64_t end, const box3i& box) {
    const vec3i dims = box.upper - box.lower + vec3i(1);
    auto slot = [&](const BuildCell& c) {
      const vec3i r = c.pos - box.lower;
      return (uint64_t(r.z) * dims.y + r.y) * dims.x + r.x;
    };
    std::sort(cells_ + begin, cells_ + end, [&](const BuildCell& a, const BuildCell& b) { return slot(a) < slot(b); });
    // Dense and sorted: slot i must hold exactly cell i (otherwise a position repeats).
    for (uint64_t i = begin; i < end; ++i)
      if (slot(cells_[i]) != i - begin)
        input_error(source_, "two cells at the same position (level " + std::to_string(level_) + ")");
    const int32_t w = level_width(level_);
    Brick b{box.lower * w, level_, dims, 0, begin};
    std::lock_guard lock(mutex_);
    bricks_.push_back(b);
  }

  BuildCell* cells_;
  int32_t level_;
  const BrickBuildOptions& opt_;
  const std::string& source_;
  std::mutex mutex_;
  std::vector<Brick> bricks_;
};

void check_cell(const Cell& c, const std::string& source) {
  if (c.level < 0 || c.level > kMaxLevel)
    input_error(source, "cell level " + std::to_string(c.level) + " out of range 0.." + std::to_string(kMaxLevel));
  const int32_t w = level_width(c.level);
  for (int a = 0; a < 3; ++a) {
    if (c.lower[a] <= -kMaxCoord || c.lower[a] >= kMaxCoord - w)
      input_error(source, "cell coordinate " + std::to_string(c.lower[a]) + " out of range");
    if (c.lower[a] % w != 0)
      input_error(source,
                  "cell at " + std::to_string(c.lower[a]) + " is not aligned to its width " + std::to_string(w));
  }
}

}  // namespace

BrickBuildResult build_bricks(std::vector<Cell>&& cells, const std::string& source_name,
                              const BrickBuildOptions& options) {
  const uint64_t n = cells.size();
  if (n >= uint64_t(UINT32_MAX)) input_error(source_name, "more than 2^32-1 cells are not supported");
  // Validate and count cells per level.
  std::vector<uint64_t> level_count(kMaxLevel + 2, 0);
  for (const Cell& c : cells) {
    check_cell(c, source_name);
    ++level_count[size_t(c.level)];
  }
  std::vector<uint64_t> level_begin(kMaxLevel + 2, 0);
  for (int l = 1; l <= kMaxLevel + 1; ++l)
    level_begin[size_t(l)] = level_begin[size_t(l - 1)] + level_count[size_t(l - 1)];

  // Bucket by level (stable, so the build is deterministic).
  std::vector<BuildCell> build(n);
  {
    std::vector<uint64_t> next(level_begin.begin(), level_begin.end());
    for (uint64_t i = 0; i < n; ++i) {
      const Cell& c = cells[i];
      build[next[size_t(c.level)]++] = {vec3i(c.lower.x >> c.level, c.lower.y >> c.level, c.lower.z >> c.level),
                                        uint32_t(i)};
    }
  }
  std::vector<Cell>().swap(cells);  // free the input

  BrickBuildResult result;
  for (int l = 0; l <= kMaxLevel; ++l) {
    if (level_count[size_t(l)] == 0) continue;
    LevelBuilder builder(build.data(), l, options, source_name);
    builder.build(level_begin[size_t(l)], level_begin[size_t(l) + 1]);
    auto bricks = builder.take_bricks();
    result.bricks.insert(result.bricks.end(), bricks.begin(), bricks.end());
  }
  tbb::parallel_sort(result.bricks.begin(), result.bricks.end(),
                     [](const Brick& a, const Brick& b) { return a.value_offset < b.value_offset; });

  result.device_cells.resize(n);
  result.input_index.resize(n);
  for (const Brick& b : result.bricks) {
    for (uint64_t i = b.value_offset; i < b.value_offset + uint64_t(b.cell_count()); ++i) {
      const int32_t w = b.width();
      result.device_cells[i] = {build[i].pos * w, b.level};
      result.input_index[i] = build[i].input;
    }
  }
  return result;
}

}  // namespace vs
