// ABR builder. Space is cut recursively at the faces of brick support boxes: a region whose
// overlapping bricks all contain it completely (no support face inside it) is a leaf, an ABR.
// Every region keeps the list of bricks whose support overlaps it, so each ABR's list is exact.
// Coordinates are doubled (half-grid units) so that supports, which reach half a cell beyond the
// brick, stay integer.
#include "volstream/amr/abrs.h"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include <tbb/parallel_sort.h>

#include "volstream/accel/bvh_sah.h"
#include "volstream/accel/refit.h"
#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"

namespace vs {
namespace {

struct Region {
  box3i box_x2;                  // half-grid units
  std::vector<uint32_t> bricks;  // bricks whose support overlaps box_x2 (open overlap)
};

struct AbrOutput {
  std::vector<Abr> abrs;
  std::vector<uint32_t> abr_bricks;
};

class AbrBuilder {
 public:
  static constexpr double kBalanceWeight = 0.05;

  AbrBuilder(const std::vector<Brick>& bricks, const std::string& source) : bricks_(bricks), source_(source) {
    supports_.reserve(bricks.size());
    for (const Brick& b : bricks) supports_.push_back(b.support_x2());
  }

  // Splits `r` at a support face. A cut through a support duplicates that brick into both
  // halves and fragments it into more ABRs, so the plane minimises the number of supports cut,
  // plus a balance term (a fraction of the count difference of the two sides) that keeps the
  // recursion shallow. Returns false when `r` is a leaf (no face strictly inside).
  bool split(Region& r, Region& left, Region& right) const {
    int best_axis = -1;
    int32_t best_plane = 0;
    double best_cost = INFINITY;
    const size_t n = r.bricks.size();
    thread_local std::vector<int32_t> lows, highs;  // scratch, reused: this runs once per node
    lows.resize(n);
    highs.resize(n);
    for (int axis = 0; axis < 3; ++axis) {
      const int32_t lo = r.box_x2.lower[axis], hi = r.box_x2.upper[axis];
      for (size_t i = 0; i < n; ++i) {
        lows[i] = supports_[r.bricks[i]].lower[axis];
        highs[i] = supports_[r.bricks[i]].upper[axis];
      }
      std::sort(lows.begin(), lows.end());
      std::sort(highs.begin(), highs.end());
      auto consider = [&](int32_t plane) {
        if (plane <= lo || plane >= hi) return;
        // Bricks reaching left of the plane, and right of it; the excess over n is the cut count.
        const double n_left = double(std::lower_bound(lows.begin(), lows.end(), plane) - lows.begin());
        const double n_right = double(highs.end() - std::upper_bound(highs.begin(), highs.end(), plane));
        const double cost = (n_left + n_right - double(n)) + kBalanceWeight * std::abs(n_left - n_right);
        if (cost < best_cost ||
            (cost == best_cost && (axis < best_axis || (axis == best_axis && plane < best_plane)))) {
          best_cost = cost;
          best_axis = axis;
          best_plane = plane;
        }
      };
      for (size_t i = 0; i < n; ++i) {
        if (i == 0 || lows[i] != lows[i - 1]) consider(lows[i]);
        if (i == 0 || highs[i] != highs[i - 1]) consider(highs[i]);
      }
    }
    if (best_axis < 0) return false;
    left.box_x2 = right.box_x2 = r.box_x2;
    left.box_x2.upper[best_axis] = best_plane;
    right.box_x2.lower[best_axis] = best_plane;
    left.bricks.clear();
    right.bricks.clear();
    for (uint32_t id : r.bricks) {
      if (supports_[id].lower[best_axis] < best_plane) left.bricks.push_back(id);
      if (supports_[id].upper[best_axis] > best_plane) right.bricks.push_back(id);
    }
    return true;
  }

  // Builds the ABRs of `r` into `out`; returns how many it emitted. Two sibling leaves with the
  // same bricks are merged back into one box: the cut between them was needed elsewhere in
  // their parent, not for them.
  size_t build_subtree(Region& r, AbrOutput& out) const {
    if (r.bricks.empty()) return 0;  // outside every support
    Region left, right;
    if (!split(r, left, right)) {
      emit_leaf(r, out);
      return 1;
    }
    std::vector<uint32_t>().swap(r.bricks);
    const size_t n_left = build_subtree(left, out);
    const size_t n_right = build_subtree(right, out);
    if (n_left == 1 && n_right == 1 && try_merge_last_two(out)) return 1;
    return n_left + n_right;
  }

 private:
  static bool try_merge_last_two(AbrOutput& out) {
    Abr& a = out.abrs[out.abrs.size() - 2];
    const Abr& b = out.abrs.back();
    if (a.brick_count != b.brick_count ||
        !std::equal(out.abr_bricks.begin() + a.first_brick, out.abr_bricks.begin() + a.first_brick + a.brick_count,
                    out.abr_bricks.begin() + b.first_brick))
      return false;
    a.box.extend(b.box);  // siblings: the union is a box
    out.abr_bricks.resize(b.first_brick);
    out.abrs.pop_back();
    return true;
  }

  void emit_leaf(const Region& r, AbrOutput& out) const {
    check_no_overlap(r);
    Abr a;
    a.box = {vec3f(r.box_x2.lower) * 0.5f, vec3f(r.box_x2.upper) * 0.5f};
    a.first_brick = uint32_t(out.abr_bricks.size());  // local; rebased when outputs are joined
    a.brick_count = uint32_t(r.bricks.size());
    int32_t finest = INT32_MAX;
    for (uint32_t id : r.bricks) finest = std::min(finest, bricks_[id].width());
    a.finest_width = float(finest);
    out.abrs.push_back(a);
    out.abr_bricks.insert(out.abr_bricks.end(), r.bricks.begin(), r.bricks.end());
  }

  // Two bricks whose cells overlap would both be listed in some leaf and overlap inside it.
  void check_no_overlap(const Region& r) const {
    uint32_t inside[8];
    int n = 0;
    for (uint32_t id : r.bricks) {
      const box3i cells = bricks_[id].cell_box();
      const box3i cells_x2{cells.lower * 2, cells.upper * 2};
      if (!cells_x2.overlaps_open(r.box_x2)) continue;
      for (int j = 0; j < n; ++j) {
        const box3i other = bricks_[inside[j]].cell_box();
        if (cells.overlaps_open(other)) overlap_error(id, inside[j]);
      }
      if (n == 8) overlap_error(id, inside[0]);  // more than 8 disjoint boxes cannot meet here
      inside[n++] = id;
    }
  }

  [[noreturn]] void overlap_error(uint32_t a, uint32_t b) const {
    const Brick &A = bricks_[a], &B = bricks_[b];
    input_error(source_, "cells overlap: level " + std::to_string(A.level) + " cells at (" + std::to_string(A.lower.x) +
                             "," + std::to_string(A.lower.y) + "," + std::to_string(A.lower.z) + ") and level " +
                             std::to_string(B.level) + " cells at (" + std::to_string(B.lower.x) + "," +
                             std::to_string(B.lower.y) + "," + std::to_string(B.lower.z) + ")");
  }

  const std::vector<Brick>& bricks_;
  const std::string& source_;
  std::vector<box3i> supports_;
};

// Splits breadth-first (keeping left-before-right order) until there is enough independent work.
std::vector<Region> expand_frontier(const AbrBuilder& builder, Region root, size_t want) {
  std::vector<Region> frontier;
  frontier.push_back(std::move(root));
  for (int round = 0; round < 16 && frontier.size() < want; ++round) {
    std::vector<Region> next;
    bool changed = false;
    for (Region& r : frontier) {
      Region left, right;
      if (r.bricks.size() > 64 && builder.split(r, left, right)) {
        next.push_back(std::move(left));
        next.push_back(std::move(right));
        changed = true;
      } else {
        next.push_back(std::move(r));
      }
    }
    frontier.swap(next);
    if (!changed) break;
  }
  return frontier;
}

// Adjacent ABRs with the same bricks whose union is a box become one. The builder's cuts serve
// other bricks, and its sibling merge (build_subtree) only joins the two sides of one cut; on
// jet 1e6 this takes the 486k ABRs to 361k. Every interval a ray crosses takes at least one
// sample, so fewer, larger ABRs mean fewer samples as well as a smaller BVH and fewer ranges.
// Greedy, one axis at a time: ABRs sorted by bricks, their face across the axis and their
// position along it, each joined to the one before when they touch. Rounds over the three axes
// repeat until one merges nothing (jet: 117k, 7k, 488, 95, ...), at most kMergeRounds of them
// (each round merges some, so a crafted input could otherwise ask for one per ABR).
// A merged ABR keeps the place of its lowest part along the axis, one of the parts that were
// neighbours in the builder's order, so the order stays subtree by subtree (abr_chunks).
constexpr int kMergeRounds = 8;

struct FaceKey {
  uint32_t list;         // the brick list's number (equal lists, equal numbers)
  float u0, v0, u1, v1;  // the face across the axis
  float lower;           // position along it
  uint32_t abr;
  bool same_face(const FaceKey& o) const {
    return list == o.list && u0 == o.u0 && v0 == o.v0 && u1 == o.u1 && v1 == o.v1;
  }
  bool operator<(const FaceKey& o) const {
    return std::tie(list, u0, v0, u1, v1, lower, abr) < std::tie(o.list, o.u0, o.v0, o.u1, o.v1, o.lower, o.abr);
  }
};

std::vector<uint32_t> brick_list_numbers(const AmrTopology& t) {
  std::vector<uint32_t> list(t.abrs.size());
  std::unordered_map<std::string_view, uint32_t> ids;
  for (size_t i = 0; i < t.abrs.size(); ++i) {
    const Abr& a = t.abrs[i];
    const std::string_view bricks(reinterpret_cast<const char*>(t.abr_bricks.data() + a.first_brick),
                                  a.brick_count * sizeof(uint32_t));
    list[i] = ids.emplace(bricks, uint32_t(ids.size())).first->second;
  }
  return list;
}

// One pass along `axis`; returns how many ABRs were merged into others (alive[i] = 0).
size_t merge_along(AmrTopology& t, const std::vector<uint32_t>& list, std::vector<uint8_t>& alive, int axis) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  std::vector<FaceKey> keys;
  for (uint32_t i = 0; i < t.abrs.size(); ++i) {
    if (!alive[i]) continue;
    const box3f& b = t.abrs[i].box;
    keys.push_back({list[i], b.lower[u], b.lower[v], b.upper[u], b.upper[v], b.lower[axis], i});
  }
  tbb::parallel_sort(keys.begin(), keys.end());
  size_t merged = 0;
  for (size_t k = 1, run = 0; k < keys.size(); ++k) {
    box3f& box = t.abrs[keys[run].abr].box;
    if (keys[k].same_face(keys[run]) && keys[k].lower == box.upper[axis]) {
      box.upper[axis] = t.abrs[keys[k].abr].box.upper[axis];
      alive[keys[k].abr] = 0;
      ++merged;
    } else {
      run = k;
    }
  }
  return merged;
}

void merge_adjacent_abrs(AmrTopology& t) {
  const std::vector<uint32_t> list = brick_list_numbers(t);
  std::vector<uint8_t> alive(t.abrs.size(), 1);
  for (int round = 0; round < kMergeRounds; ++round) {
    size_t merged = 0;
    for (int axis = 0; axis < 3; ++axis) merged += merge_along(t, list, alive, axis);
    if (merged == 0) break;
  }
  std::vector<Abr> abrs;
  std::vector<uint32_t> bricks;
  for (size_t i = 0; i < t.abrs.size(); ++i) {
    if (!alive[i]) continue;
    Abr a = t.abrs[i];
    const uint32_t* first = t.abr_bricks.data() + a.first_brick;
    a.first_brick = uint32_t(bricks.size());
    bricks.insert(bricks.end(), first, first + a.brick_count);
    abrs.push_back(a);
  }
  t.abrs = std::move(abrs);
  t.abr_bricks = std::move(bricks);
}

}  // namespace

void build_abrs(AmrTopology& topology, const std::string& source_name) {
  topology.abrs.clear();
  topology.abr_bricks.clear();
  if (topology.bricks.empty()) return;
  AbrBuilder builder(topology.bricks, source_name);
  Region root;
  root.box_x2 = box3i::make_empty();
  for (uint32_t i = 0; i < topology.bricks.size(); ++i) {
    root.box_x2.extend(topology.bricks[i].support_x2());
    root.bricks.push_back(i);
  }
  std::vector<Region> frontier = expand_frontier(builder, std::move(root), 256);
  std::vector<AbrOutput> outputs(frontier.size());
  parallel_for("abr_build", int64_t(frontier.size()),
               [&](int64_t i) { builder.build_subtree(frontier[size_t(i)], outputs[size_t(i)]); });
  for (AbrOutput& out : outputs) {
    const uint32_t base = uint32_t(topology.abr_bricks.size());
    if (topology.abr_bricks.size() + out.abr_bricks.size() >= UINT32_MAX)
      input_error(source_name, "too many ABR brick references");
    for (Abr& a : out.abrs) a.first_brick += base;
    topology.abrs.insert(topology.abrs.end(), out.abrs.begin(), out.abrs.end());
    topology.abr_bricks.insert(topology.abr_bricks.end(), out.abr_bricks.begin(), out.abr_bricks.end());
    out = {};
  }
  merge_adjacent_abrs(topology);
}

std::vector<box3f> abr_boxes(const AmrTopology& topology) {
  std::vector<box3f> boxes;
  boxes.reserve(topology.abrs.size());
  for (const Abr& a : topology.abrs) boxes.push_back(a.box);
  return boxes;
}

Bvh build_abr_bvh(const AmrTopology& topology) {
  if (!topology.abr_bvh.nodes.empty()) return topology.abr_bvh;
  return build_bvh_sah(abr_boxes(topology));
}

std::vector<AbrChunk> abr_chunks(const std::vector<Abr>& abrs) {
  std::vector<AbrChunk> chunks(chunk_count(abrs.size()), AbrChunk{box3f::make_empty(), 0.f});
  for (uint32_t c = 0; c < chunks.size(); ++c)
    for (uint64_t i = chunk_first(c); i < chunk_first(c) + chunk_size(c, abrs.size()); ++i) {
      chunks[c].box.extend(abrs[i].box);
      chunks[c].finest_width = std::max(chunks[c].finest_width, abrs[i].finest_width);
    }
  return chunks;
}

}  // namespace vs
