// Runs the integrator (integrator.h) for every pixel of a frame on all CPU cores.
#pragma once
#include <algorithm>
#include <cstdint>

#include "volstream/backend/parallel.h"
#include "volstream/render/integrators/integrator.h"

namespace vs {

// 8x8 tiles: neighbouring rays visit the same regions and cells, which keeps them in cache.
template <typename V>
void render_frame_cpu(const FrameView<V>& view) {
  constexpr uint32_t kTile = 8;
  const uint32_t tiles_x = (view.width + kTile - 1) / kTile, tiles_y = (view.height + kTile - 1) / kTile;
  with_optics(view, [&](auto optics) {
    parallel_for("render", int64_t(tiles_x) * tiles_y, [&](int64_t tile) {
      const uint32_t x0 = uint32_t(tile % tiles_x) * kTile, y0 = uint32_t(tile / tiles_x) * kTile;
      for (uint32_t y = y0; y < std::min(y0 + kTile, view.height); ++y)
        for (uint32_t x = x0; x < std::min(x0 + kTile, view.width); ++x) render_pixel<optics.value>(view, x, y);
    });
  });
}

}  // namespace vs
