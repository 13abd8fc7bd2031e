// What an integrator is asked to do, per frame: sampling, marching scheme, isosurfaces, shading.
#pragma once
#include <cstdint>

#include "volstream/core/math.h"

namespace vs {

inline constexpr uint32_t kMaxIso = 8;

// How a region's interval is cut into steps (render/integrators/integrator.h).
enum class March : uint32_t {
  // Paper 000 (ABRs): n equal steps no longer than width / rate, samples at a jittered offset
  // inside each step (against wood-grain).
  equal_jittered = 0,
  // Paper 004 (blocks): steps of exactly width / rate from the entry, the last one shortened to
  // end at the exit (its opacity uses that true length), samples at the middle of each step.
  fixed_midpoint = 1,
  // Meshes: steps of width / rate on a lattice fixed along the ray (sample m at (m + jitter) *
  // step from the ray's origin), so an interval's samples do not depend on where it begins: the
  // macrocells of one width sample as one interval would, merged or not, skipped or not, on one
  // rank or several; and no interval rounds its step count up.
  lattice = 2,
};

struct IntegratorSettings {
  float rate = 2.f;       // samples per cell width (the region's finest width when adaptive)
  uint32_t adaptive = 1;  // 0: step at the dataset's finest width in every region
  float ref_step = 1.f;   // world length over which a table alpha applies unchanged
  uint32_t jitter = 1;    // equal_jittered, lattice: per-pixel start offset (deterministic hash)
  uint32_t shade = 0;     // gradient (headlight) shading of the volume
  uint32_t spp = 1;       // rays per pixel; > 1 spreads them over the pixel
  uint32_t seed = 0;      // varies the jitter pattern
  March march = March::equal_jittered;
  uint32_t iso_count = 0;
  float iso[kMaxIso] = {};
  float iso_alpha = 1.f;  // opacity of the isosurfaces
  // Stop a ray at opacity kOpaque. Off for data-parallel ranks (mpi/): a rank cannot know how
  // opaque the ranks in front of it are, so stopping early would drop a different tail of the
  // ray than one process does.
  uint32_t early_termination = 1;
  // CPU: march transfer-function intervals without isosurfaces or shading in batches of samples
  // (integrator.h, march_interval_batched; the same image). 0: one sample at a time, the GPU's
  // loop, which tests compare with.
  uint32_t cpu_batches = 1;
};

}  // namespace vs
