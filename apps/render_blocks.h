// The block raycaster and blackbody optics (paper 004) as options of `render`.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

#include "volstream/io/dataset.h"
#include "volstream/render/integrators/abr_renderer.h"

namespace vs::cli {

struct BlockRenderArgs {
  std::string integrator = "abr", reconstruction = "trilinear", optics = "tf", temperature_field = "temperature";
  std::string density_scale = "auto";  // auto (the transfer function's scale), linear or log
  double absorption = 0.25, emission = 4, emission_power = 0;  // power 0: 1 linear, 4 log
  Device device = Device::cpu;  // not an option of its own: the caller sets it from `render --device`
  bool enabled() const { return integrator == "blocks" || optics == "blackbody"; }
};

void add_block_render_options(CLI::App* cmd, BlockRenderArgs& a);

// Renders with the kd-tree block raycaster (blackbody optics needs it: the ABR integrator has
// no two-field model). The transfer function's value range normalises the density for the
// blackbody model: rho / hi (linear, as the paper) or the log10 position in [lo, hi] (--log and
// the cosmo demo's look, whose densities span 7 decades); --density-scale overrides the choice.
Image render_with_blocks(const Dataset& ds, int step, int field, const TransferTable& tf,
                         const Camera& camera, const FrameSettings& fs, const BlockRenderArgs& a, FrameStats* stats);

}  // namespace vs::cli
