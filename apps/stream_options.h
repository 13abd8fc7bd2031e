// Options shared by `play` and `bench stream`: which steps to play and how to render them.
// The render options are a subset of `render`'s (field, transfer function, range, size, camera),
// fixed for the whole animation so that frames of different steps are comparable.
#pragma once
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "volstream/io/dataset.h"
#include "volstream/stream/render_stages.h"

namespace vs::cli {

// "A:B" (half-open), "A:B:S" (stride S) or "17,3,250" (listed, in that order); empty = all.
// UsageError for malformed text, an empty range or a step outside [0, step_count).
std::vector<int> parse_steps(const std::string& text, int step_count);

struct StreamRenderArgs {
  std::string field, tf = "viridis", range, size = "256x256", background = "0.06,0.06,0.08", device = "cpu";
  std::string camera_pos, camera_at, camera_up;
  double fov = 35, rate = 2;
  bool log = false, no_skip = false;
};
void add_stream_render_options(CLI::App* cmd, StreamRenderArgs& args);

struct StreamRender {
  int field = 0;
  stream::RenderSetup setup;
  vec3f background;
};
// The transfer function's range defaults to the union of the field's ranges over all steps.
StreamRender make_stream_render(const Dataset& dataset, const StreamRenderArgs& args);

}  // namespace vs::cli
