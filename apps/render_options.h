// The render options shared by `render`, `play` and `bench stream`: one struct, one registration,
// one translation into what the renderer takes (transfer function, frame settings, camera,
// device). What differs between the commands is passed in: the defaults (the struct's values
// when the options are registered) and the steps whose value ranges make the transfer
// function's default range (one step for `render`, all steps for a stream, so that a frame
// looks the same however it is reached).
#pragma once
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "volstream/frame/frame_renderer.h"
#include "volstream/io/dataset.h"
#include "volstream/stream/render_stages.h"

namespace vs::cli {

struct RenderOptions {
  std::string field, tf = "auto", range, opacity, layers, iso, color_field;
  std::string camera_pos, camera_at, camera_up, size = "512x512", background = "0.06,0.06,0.08", device = "auto";
  uint32_t spp = 1;
  double fov = 35, rate = 2, iso_alpha = 1, unit_distance = 0;
  bool log = false, ortho = false, no_skip = false, no_adaptive = false, no_jitter = false, shade = false;
  bool stored_ranges = false, alpha = false, brick_ranges = false;
  std::string encoding = "stored";  // meshes: stored | reference | compact
  // Integrator and optics (render only; paper 004's block raycaster and blackbody model).
  std::string integrator = "auto", reconstruction = "trilinear", optics = "tf", temperature_field = "temperature";
  std::string density_scale = "auto";                          // auto (the transfer function's scale), linear or log
  double absorption = 0.25, emission = 4, emission_power = 0;  // power 0: 1 linear, 4 log
  // Not an option: with no --field, render the built-in demo's look field (vorticity, density:
  // render) or the dataset's first field (play, bench: their frames stay what they were).
  bool field_from_look = true;
};

// `play`'s and `bench stream`'s defaults: 256x256 frames (there are many), the render stage on
// the CPU unless --device says otherwise, the first field in viridis (what they rendered before
// the options were shared; `--tf auto --field vorticity` gives render's demo look).
RenderOptions stream_render_defaults();

enum class RenderContext { image, stream };

// Registers every render option on `cmd`; the values in `o` are the defaults --help shows.
// `context` changes help texts (e.g. what the default range is); the integrator and optics
// options are registered for images only (the pipeline streams one field per step).
void add_render_options(CLI::App* cmd, RenderOptions& o, RenderContext context);
void add_integrator_options(CLI::App* cmd, RenderOptions& o);

// Everything a frame needs, parsed and checked: the library's request plus what only the output
// needs.
struct RenderPlan {
  FrameRequest request;
  vec3f background;                   // --background (sRGB, as the image writers take it)
  Device device = Device::cpu;        // --device
  stream::RenderSetup setup() const;  // what the streaming stages take
};

// Checks every option and builds the plan. The transfer function's default range (and the
// colour field's) is the union of the field's ranges over `range_steps`.
RenderPlan make_render_plan(const RenderOptions& o, const Dataset& dataset, const std::vector<int>& range_steps);

// `play` and `bench stream`: UsageError for the options the frame pipeline cannot honour
// (--color-field, --stored-ranges, --alpha), then the plan with the range over all steps.
RenderPlan make_stream_render_plan(const RenderOptions& o, const Dataset& dataset);

// The parts, for callers that need only one.
// An image's float RGBA takes 16 bytes a pixel: 8192x8192 is 1 GiB, the most --size allows.
inline constexpr double kMaxPixels = 8192.0 * 8192.0;
void parse_size(const std::string& text, uint32_t& width, uint32_t& height);  // WxH, 1..16384, W*H <= kMaxPixels
int render_field(const RenderOptions& o, const Dataset& dataset);             // --field, else see field_from_look
IntegratorSettings make_integrator_settings(const RenderOptions& o);
Camera make_camera(const RenderOptions& o, const Dataset& dataset, uint32_t width, uint32_t height);

}  // namespace vs::cli
