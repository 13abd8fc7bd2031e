// Runs the integrator (integrator.h) for every pixel of a frame on all CPU cores.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>

#include "volstream/backend/parallel.h"
#include "volstream/render/integrators/integrator.h"

namespace vs {

// 8x8 tiles: neighbouring rays visit the same regions and cells, which keeps them in cache.
// Returns the samples taken, summed per tile (view.sample_counts, per pixel, is optional: a
// buffer of 4 B a pixel is a megabyte of fresh pages at 512x512 for a sum).
template <typename V>
uint64_t render_frame_cpu(const FrameView<V>& view) {
  constexpr uint32_t kTile = 8;
  const uint32_t tiles_x = (view.width + kTile - 1) / kTile, tiles_y = (view.height + kTile - 1) / kTile;
  std::atomic<uint64_t> samples{0};
  with_optics(view, [&](auto optics) {
    parallel_for("render", int64_t(tiles_x) * tiles_y, [&](int64_t tile) {
      const uint32_t x0 = uint32_t(tile % tiles_x) * kTile, y0 = uint32_t(tile / tiles_x) * kTile;
      uint64_t taken = 0;
      for (uint32_t y = y0; y < std::min(y0 + kTile, view.height); ++y)
        for (uint32_t x = x0; x < std::min(x0 + kTile, view.width); ++x)
          taken += render_pixel<optics.value>(view, x, y);
      samples.fetch_add(taken, std::memory_order_relaxed);
    });
  });
  return samples.load();
}

}  // namespace vs
