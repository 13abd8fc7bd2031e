#include "stream_options.h"
#include "parse_util.h"

#include <cmath>
#include <sstream>

#include "volstream/core/error.h"

namespace vs::cli {
namespace {

// A whole decimal integer, or UsageError naming `what`.
long long parse_int(const std::string& text, const std::string& what) {
  size_t used = 0;
  long long v = 0;
  try {
    v = std::stoll(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw UsageError(what + ": '" + text + "' is not an integer");
  return v;
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> parts;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, sep)) parts.push_back(item);
  if (!text.empty() && text.back() == sep) parts.emplace_back();
  return parts;
}

int checked_step(long long s, int step_count) {
  if (s < 0 || s >= step_count)
    throw UsageError("--steps: step " + std::to_string(s) + " out of range 0.." + std::to_string(step_count - 1));
  return int(s);
}

}  // namespace

std::vector<int> parse_steps(const std::string& text, int step_count) {
  std::vector<int> steps;
  if (text.empty()) {
    for (int s = 0; s < step_count; ++s) steps.push_back(s);
    return steps;
  }
  if (text.find(':') == std::string::npos) {
    for (const std::string& item : split(text, ',')) steps.push_back(checked_step(parse_int(item, "--steps"), step_count));
    return steps;
  }
  const auto parts = split(text, ':');
  if (parts.size() > 3) throw UsageError("--steps expects A:B[:S] or a list S1,S2,...");
  const long long a = parse_int(parts[0], "--steps"), b = parse_int(parts[1], "--steps");
  const long long stride = parts.size() == 3 ? parse_int(parts[2], "--steps") : 1;
  if (stride < 1) throw UsageError("--steps: the stride must be at least 1");
  if (a >= b) throw UsageError("--steps " + text + ": empty range (A:B is half-open, A < B)");
  checked_step(a, step_count);
  checked_step(b - 1, step_count);
  for (long long s = a; s < b; s += stride) steps.push_back(int(s));
  return steps;
}

void add_stream_render_options(CLI::App* cmd, StreamRenderArgs& a) {
  cmd->add_option("--field", a.field, "field to render (default: the first)");
  cmd->add_option("--tf", a.tf, "colour map: viridis, inferno, cool-warm, grayscale, blackbody, or a ParaView .json")
      ->capture_default_str();
  cmd->add_option("--range", a.range, "LO,HI transfer-function range (default: the field's range over all steps)");
  cmd->add_flag("--log", a.log, "log10 value scale (a range reaching zero starts at HI*1e-6)");
  cmd->add_option("--size", a.size, "image size WxH")->capture_default_str();
  cmd->add_option("--camera-pos", a.camera_pos, "X,Y,Z camera position, world units (default: fitted diagonal view)");
  cmd->add_option("--camera-at", a.camera_at, "X,Y,Z point looked at (default: the domain's centre)");
  cmd->add_option("--camera-up", a.camera_up, "X,Y,Z up direction")->default_str("0,1,0");
  cmd->add_option("--fov", a.fov, "vertical field of view, degrees")->capture_default_str();
  cmd->add_option("--rate", a.rate, "samples per cell width")->capture_default_str();
  cmd->add_flag("--no-skip", a.no_skip, "no empty-space skipping");
  cmd->add_option("--background", a.background, "R,G,B background in [0,1] (sRGB)")->capture_default_str();
  cmd->add_option("--device", a.device, "auto | cpu | cuda (render stage only)")->capture_default_str();
}

namespace {

void set_colors(const std::string& tf, TransferFunctionSpec& spec) {
  if (tf.size() > 5 && tf.substr(tf.size() - 5) == ".json") {
    const ParaviewColorMap cm = load_paraview_color_map(tf);
    spec.colors = cm.colors;
    spec.opacity = cm.opacity;
    return;
  }
  spec.colors = builtin_color_map(tf);
  if (spec.colors.empty()) throw UsageError("unknown transfer function '" + tf + "'");
}

// Over all steps, not just the played ones, so that a step looks the same however it is reached.
void set_range(const StreamRenderArgs& a, const FieldInfo& f, TransferFunctionSpec& spec) {
  Range r{INFINITY, -INFINITY};
  for (const Range& s : f.step_ranges) r = {std::min(r.lo, s.lo), std::max(r.hi, s.hi)};
  if (!a.range.empty()) {
    const auto v = parse_numbers(a.range, "--range");
    if (v.size() != 2 || !(v[0] < v[1])) throw UsageError("--range expects LO,HI with LO < HI");
    r = {float(v[0]), float(v[1])};
  }
  if (!(r.lo <= r.hi)) r = {0.f, 1.f};  // no finite value in any played step
  if (spec.log_scale && !(r.hi > 0)) throw UsageError("--log: the value range has no positive values");
  if (spec.log_scale && !(r.lo > 0)) r.lo = r.hi * 1e-6f;
  spec.lo = r.lo;
  spec.hi = r.hi;
}

void set_size(const std::string& text, FrameSettings& fs) {
  const auto v = parse_numbers(text, "--size", 'x');
  if (v.size() != 2 || v[0] < 1 || v[1] < 1 || v[0] > 16384 || v[1] > 16384 || v[0] != std::floor(v[0]) ||
      v[1] != std::floor(v[1]))
    throw UsageError("--size expects WxH with 1 <= W, H <= 16384");
  fs.width = uint32_t(v[0]);
  fs.height = uint32_t(v[1]);
}

Camera make_camera(const StreamRenderArgs& a, const Dataset& ds, const FrameSettings& fs) {
  const AmrRenderer bounds_only(ds.topology(), ds.manifest().transform);
  Camera c = default_camera(bounds_only.world_bounds(), double(fs.width) / fs.height);
  if (!a.camera_at.empty()) c.look_at = parse_vec3(a.camera_at, "--camera-at");
  if (!a.camera_pos.empty()) c.position = parse_vec3(a.camera_pos, "--camera-pos");
  if (!a.camera_up.empty()) c.up = parse_vec3(a.camera_up, "--camera-up");
  if (!(a.fov > 0 && a.fov < 180)) throw UsageError("--fov must be in (0, 180)");
  c.fov_deg = a.fov;
  make_camera_view(c, fs.width, fs.height);  // rejects degenerate cameras now, not at the first frame
  return c;
}

}  // namespace

StreamRender make_stream_render(const Dataset& ds, const StreamRenderArgs& a) {
  const DatasetManifest& m = ds.manifest();
  StreamRender out;
  out.field = a.field.empty() ? 0 : m.field_index(a.field);
  if (out.field < 0) throw UsageError("no field '" + a.field + "' in " + ds.dir().string());
  TransferFunctionSpec& spec = out.setup.tf;
  spec.log_scale = a.log;
  set_colors(a.tf, spec);
  set_range(a, m.fields[size_t(out.field)], spec);
  FrameSettings& fs = out.setup.settings;
  set_size(a.size, fs);
  if (!(a.rate > 0 && a.rate <= 64)) throw UsageError("--rate must be in (0, 64]");
  fs.integrator.rate = float(a.rate);
  fs.integrator.ref_step = 0.f;  // the renderer's default: 1/256 of the domain
  fs.skip = !a.no_skip;
  out.setup.camera = make_camera(a, ds, fs);
  out.setup.device = resolve_device(a.device);
  const vec3d bg = parse_vec3(a.background, "--background");
  out.background = vec3f(bg);
  return out;
}

}  // namespace vs::cli
