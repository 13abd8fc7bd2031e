// The AMR data model: cells, bricks, active brick regions (ABRs).
//
// Coordinates are in "grid units": integers in units of the finest cell width. A cell of level L
// (L = log2 of its width, so level 0 is the finest, as in ExaBrick files) has width 2^L and its
// lower corner is a multiple of 2^L. World coordinates are origin + grid * cell_size.
#pragma once
#include <cstdint>
#include <vector>

#include "volstream/accel/bvh.h"
#include "volstream/core/math.h"

namespace vs {

inline constexpr int kMaxLevel = 24;           // widths up to 2^24 finest cells
inline constexpr int32_t kMaxCoord = 1 << 28;  // |grid coordinate| bound, keeps 2*coord in int32

struct Cell {
  vec3i lower;    // lower corner in grid units
  int32_t level;  // log2 of the width in grid units
};
static_assert(sizeof(Cell) == 16);

VS_HOST_DEVICE constexpr int32_t level_width(int32_t level) { return int32_t(1) << level; }

// A box of same-level cells, stored x fastest, starting at value_offset in every field array.
struct Brick {
  vec3i lower;  // grid units
  int32_t level;
  vec3i dims;  // cells per axis
  uint32_t reserved = 0;
  uint64_t value_offset;  // index of the brick's first cell in device order
  VS_HOST_DEVICE constexpr int32_t width() const { return level_width(level); }
  VS_HOST_DEVICE constexpr int64_t cell_count() const { return int64_t(dims.x) * dims.y * dims.z; }
  VS_HOST_DEVICE constexpr box3i cell_box() const { return {lower, lower + dims * width()}; }
  // The region where the brick's tent basis functions are non-zero: its box grown by half a cell,
  // in half-grid units (doubled coordinates) so that it stays integer.
  VS_HOST_DEVICE constexpr box3i support_x2() const {
    const int32_t w = width();
    return {lower * 2 - vec3i(w), (lower + dims * w) * 2 + vec3i(w)};
  }
};
static_assert(sizeof(Brick) == 40);

// An active brick region: a box of space (in grid units) in which the same set of bricks has
// non-zero support. ABRs are disjoint and cover the union of all brick supports.
struct Abr {
  box3f box;             // grid units (multiples of 1/2)
  uint32_t first_brick;  // into AmrTopology::abr_bricks
  uint32_t brick_count;
  float finest_width;  // smallest cell width among its bricks (grid units)
};
static_assert(sizeof(Abr) == 36);

// Per-ABR value range of one field at one step. An ABR with no finite value has lo > hi.
struct Range {
  float lo, hi;
};

struct AmrTopology {
  std::vector<Brick> bricks;  // in device order (sorted by value_offset)
  std::vector<Abr> abrs;
  std::vector<uint32_t> abr_bricks;  // concatenated brick lists of all ABRs
  // The BVH over the ABR boxes as a dataset stores it (its topology, made at convert), refit to
  // the ABR boxes at load. Empty when not stored (older datasets, a rank's part): build_abr_bvh
  // builds one then. A renderer of this topology uses it as it is (no copy).
  Bvh abr_bvh;
  uint64_t cell_count = 0;
};

// A read-only view handed to kernels (host or device pointers).
struct AmrView {
  const Brick* bricks = nullptr;
  const Abr* abrs = nullptr;
  const uint32_t* abr_bricks = nullptr;
  const float* values = nullptr;  // one field, device order
  uint32_t brick_count = 0, abr_count = 0;
};

inline AmrView make_view(const AmrTopology& t, const float* values) {
  return {t.bricks.data(),           t.abrs.data(),          t.abr_bricks.data(), values,
          uint32_t(t.bricks.size()), uint32_t(t.abrs.size())};
}

}  // namespace vs
