// render: one image of a dataset (or a built-in demo): DVR and/or isosurfaces through the ABRs.
#include <unistd.h>
#include "parse_util.h"

#include <chrono>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "commands.h"
#include "render_blocks.h"
#include "volstream/amr/demo.h"
#include "volstream/core/error.h"
#include "volstream/cuda/backend.h"
#include "volstream/io/dataset.h"
#include "volstream/io/image.h"
#include "volstream/render/abr_ranges.h"
#include "volstream/render/renderer.h"

namespace vs::cli {
namespace {

struct RenderArgs {
  std::string dir, demo, field, tf = "auto", range, opacity, iso, color_field;
  std::string camera_pos, camera_at, camera_up, size = "512x512", background = "0.06,0.06,0.08", device = "auto";
  std::string output;
  double cells = 1e6;
  int step = 0;
  uint32_t spp = 1;
  double fov = 35, rate = 2, iso_alpha = 1, ref_step = 0;
  bool log = false, ortho = false, no_skip = false, no_adaptive = false, shade = false, alpha = false;
  bool no_jitter = false, stored_ranges = false;
  BlockRenderArgs blocks;  // --integrator, --optics, ... (cmd_render_blocks.cpp)
};

void parse_size(const std::string& text, uint32_t& w, uint32_t& h) {
  const auto v = parse_numbers(text, "--size", 'x');
  if (v.size() != 2 || v[0] < 1 || v[1] < 1 || v[0] > 16384 || v[1] > 16384 || v[0] != std::floor(v[0]) ||
      v[1] != std::floor(v[1]))
    throw UsageError("--size expects WxH with 1 <= W, H <= 16384");
  w = uint32_t(v[0]);
  h = uint32_t(v[1]);
}

// Built-in demos have a field and a look that show them well; other datasets: the first field.
struct Look {
  std::string field, color_map;
  float log_decades = 0;              // > 0: log scale over [hi / 10^decades, hi]
  std::vector<OpacityPoint> opacity;  // normalised positions; empty: default ramp
};
Look default_look(const DatasetManifest& m) {
  if (m.field_index("vorticity") >= 0)  // jet: body, wingtip vortices and the vortex street
    return {"vorticity", "inferno", 3.2f, {{0.15f, 0.f}, {0.46f, 0.01f}, {0.77f, 0.03f}, {0.93f, 0.4f}, {1.f, 0.9f}}};
  if (m.field_index("density") >= 0)  // cosmo: filaments and clumps over many decades
    return {"density", "inferno", 7.f, {{0.19f, 0.f}, {0.29f, 0.03f}, {0.43f, 0.1f}, {0.72f, 0.5f}, {1.f, 0.9f}}};
  return {m.fields.at(0).name, "viridis", 0.f, {}};
}

int field_or_throw(const DatasetManifest& m, const std::string& name, const std::string& dir) {
  const int f = m.field_index(name);
  if (f < 0) throw UsageError("no field '" + name + "' in " + dir);
  return f;
}

// Value range: --range, else the field's global range at this step (the look's decades below
// its maximum on a log scale). On a log scale the lower end must be positive: it becomes
// hi * 1e-6 when the data reach down to zero or below.
void value_range(const RenderArgs& a, const FieldInfo& f, float decades, TransferFunctionSpec& spec) {
  Range r = f.step_ranges.at(size_t(a.step));
  if (!a.range.empty()) {
    const auto v = parse_numbers(a.range, "--range");
    if (v.size() != 2 || !(v[0] < v[1])) throw UsageError("--range expects LO,HI with LO < HI");
    r = {float(v[0]), float(v[1])};
  } else if (spec.log_scale && decades > 0 && r.hi > 0) {
    r.lo = std::max(r.lo, r.hi * std::pow(10.f, -decades));
  }
  if (!(r.lo <= r.hi)) r = {0.f, 1.f};  // a field with no finite value
  if (spec.log_scale && !(r.hi > 0)) throw UsageError("--log: the value range has no positive values");
  if (spec.log_scale && !(r.lo > 0)) r.lo = r.hi * 1e-6f;
  spec.lo = r.lo;
  spec.hi = r.hi;
}

// --tf NAME | FILE.json: colours (and a ParaView preset's opacity points, when it has any).
void colors_from(const std::string& tf, TransferFunctionSpec& spec) {
  if (tf.size() > 5 && tf.substr(tf.size() - 5) == ".json") {
    const ParaviewColorMap cm = load_paraview_color_map(tf);
    spec.colors = cm.colors;
    if (spec.opacity.empty()) spec.opacity = cm.opacity;
    return;
  }
  spec.colors = builtin_color_map(tf);
  if (spec.colors.empty()) {
    std::string names;
    for (const auto& n : builtin_color_map_names()) names += (names.empty() ? "" : ", ") + n;
    throw UsageError("unknown transfer function '" + tf + "' (" + names + ", or a ParaView .json file)");
  }
}

// --opacity V:A,... with V in data units (also with --log) and A in [0, 1].
std::vector<OpacityPoint> parse_opacity(const std::string& text, const TransferFunctionSpec& spec) {
  std::vector<OpacityPoint> pts;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto colon = item.find(':');
    if (colon == std::string::npos) throw UsageError("--opacity expects VALUE:ALPHA pairs, got '" + item + "'");
    const double v = parse_numbers(item.substr(0, colon), "--opacity").at(0);
    const double alpha = parse_numbers(item.substr(colon + 1), "--opacity").at(0);
    if (alpha < 0 || alpha > 1) throw UsageError("--opacity: alpha must be in [0, 1]");
    const float x = normalised_position(spec, v);
    if (std::isnan(x)) throw UsageError("--opacity: value " + item.substr(0, colon) + " is not positive (--log)");
    pts.push_back({x, float(alpha)});
  }
  std::sort(pts.begin(), pts.end(), [](const OpacityPoint& a, const OpacityPoint& b) { return a.x < b.x; });
  return pts;
}

Camera make_camera(const RenderArgs& a, const AmrRenderer& r, uint32_t w, uint32_t h) {
  const Box3<double> box = r.world_bounds();
  Camera c = default_camera(box, double(w) / h);
  if (!a.camera_at.empty()) c.look_at = parse_vec3(a.camera_at, "--camera-at");
  if (!a.camera_pos.empty()) c.position = parse_vec3(a.camera_pos, "--camera-pos");
  if (!a.camera_up.empty()) c.up = parse_vec3(a.camera_up, "--camera-up");
  if (!(a.fov > 0 && a.fov < 180)) throw UsageError("--fov must be in (0, 180)");
  c.fov_deg = a.fov;
  c.ortho = a.ortho;
  return c;
}

IntegratorSettings integrator_settings(const RenderArgs& a) {
  IntegratorSettings s;
  if (!(a.rate > 0 && a.rate <= 64)) throw UsageError("--rate must be in (0, 64]");
  if (a.spp < 1 || a.spp > 4096) throw UsageError("--spp must be in [1, 4096]");
  if (!(a.iso_alpha >= 0 && a.iso_alpha <= 1)) throw UsageError("--iso-alpha must be in [0, 1]");
  if (a.ref_step < 0) throw UsageError("--unit-distance must be positive");
  s.rate = float(a.rate);
  s.adaptive = a.no_adaptive ? 0 : 1;
  s.jitter = a.no_jitter ? 0 : 1;
  s.shade = a.shade ? 1 : 0;
  s.spp = a.spp;
  s.ref_step = float(a.ref_step);
  s.iso_alpha = float(a.iso_alpha);
  if (!a.iso.empty()) {
    const auto iso = parse_numbers(a.iso, "--iso");
    if (iso.size() > kMaxIso) throw UsageError("--iso takes at most " + std::to_string(kMaxIso) + " values");
    for (double v : iso) s.iso[s.iso_count++] = float(v);
  }
  return s;
}

// A demo written to a temporary dataset directory, removed again on exit.
struct TempDemo {
  std::filesystem::path dir;
  TempDemo(const std::string& name, double cells) {
    dir = std::filesystem::temp_directory_path() / ("volstream_render_" + name + "_" + std::to_string(getpid()));
    std::filesystem::remove_all(dir);
    auto source = make_demo({name, uint64_t(cells), 1});
    convert_to_dataset(*source, dir, {true});
  }
  ~TempDemo() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

void run_render(const RenderArgs& a) {
  if (a.dir.empty() == a.demo.empty()) throw UsageError("give either a dataset directory or --demo jet|cosmo");
  std::unique_ptr<TempDemo> demo;
  auto t_load = std::chrono::steady_clock::now();
  if (!a.demo.empty()) demo = std::make_unique<TempDemo>(a.demo, a.cells);
  const std::string dir = demo ? demo->dir.string() : a.dir;
  const Dataset ds(dir);
  const DatasetManifest& m = ds.manifest();
  if (a.step < 0 || a.step >= m.step_count())
    throw UsageError("step " + std::to_string(a.step) + " out of range 0.." + std::to_string(m.step_count() - 1));
  const Look look = default_look(m);
  const int field = field_or_throw(m, a.field.empty() ? look.field : a.field, dir);
  const bool demo_look = a.field.empty() || a.field == look.field;

  TransferFunctionSpec spec;
  const bool use_look = demo_look && a.tf == "auto";
  spec.log_scale = a.log || (use_look && look.log_decades > 0);
  value_range(a, m.fields[size_t(field)], use_look ? look.log_decades : 0.f, spec);
  if (!a.opacity.empty()) spec.opacity = parse_opacity(a.opacity, spec);
  else if (use_look) spec.opacity = look.opacity;
  colors_from(a.tf == "auto" ? (demo_look ? look.color_map : "viridis") : a.tf, spec);
  const TransferTable tf(spec);

  FrameSettings fs;
  parse_size(a.size, fs.width, fs.height);
  fs.integrator = integrator_settings(a);
  fs.skip = !a.no_skip;
  const Device device = resolve_device(a.device);

  const std::vector<float> values = ds.load_values(field, a.step);
  // Tight ranges (render/abr_ranges.h) cull far more than the stored per-brick ones.
  const auto t_ranges = std::chrono::steady_clock::now();
  const std::vector<Range> abr_ranges = a.stored_ranges ? ds.load_abr_ranges(field, a.step)
                                                        : compute_tight_abr_ranges(ds.topology(), values.data());
  const double ranges_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_ranges).count();
  std::vector<float> color_values;
  std::unique_ptr<TransferTable> color_tf;
  if (!a.color_field.empty()) {
    const int cf = field_or_throw(m, a.color_field, dir);
    color_values = ds.load_values(cf, a.step);
    TransferFunctionSpec cspec = spec;
    cspec.log_scale = a.log;
    Range r = m.fields[size_t(cf)].step_ranges.at(size_t(a.step));
    if (cspec.log_scale && !(r.lo > 0)) r.lo = r.hi * 1e-6f;
    cspec.lo = r.lo;
    cspec.hi = r.hi;
    color_tf = std::make_unique<TransferTable>(cspec);
  }
  const double load_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_load).count();

  AmrRenderer renderer(ds.topology(), m.transform);
  FrameStats stats;
  renderer.classify(abr_ranges, tf, fs.integrator, fs.skip, &stats);
  const Camera camera = make_camera(a, renderer, fs.width, fs.height);
  const std::clock_t cpu0 = std::clock();
  const Image img = a.blocks.enabled()
                        ? render_with_blocks(ds, a.step, field, tf, camera, fs, a.blocks, &stats)
                        : renderer.render(device, values.data(), tf, color_tf ? color_values.data() : nullptr,
                                          color_tf.get(), camera, fs, &stats);
  const double cpu_s = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
  ImageWriteOptions wo;
  wo.alpha = a.alpha;
  wo.background = vec3f(parse_vec3(a.background, "--background"));
  write_image(img, a.output, wo);

  const std::string dev = device == Device::cuda ? "cuda (" + cuda::device_name() + ")" : "cpu";
  std::printf("device: %s\n", dev.c_str());
  std::printf("field %s step %d, range [%g, %g]%s, %llu of %zu ABRs visible%s\n", m.fields[size_t(field)].name.c_str(),
              a.step, spec.lo, spec.hi, spec.log_scale ? " (log)" : "", (unsigned long long)stats.visible_abrs,
              ds.topology().abrs.size(), fs.skip ? "" : " (no skipping)");
  std::printf("load %.3fs, ranges %.4fs%s, classify %.4fs, refit %.4fs%s\n", load_s - ranges_s, ranges_s,
              a.stored_ranges ? " (stored)" : "", stats.classify_seconds, stats.refit_seconds,
              device == Device::cuda ? (", upload " + std::to_string(stats.upload_seconds) + "s").c_str() : "");
  std::printf("render %ux%u: %.3fs (%.3fs CPU time), %.1f M samples, %.1f M samples/s -> %s\n", fs.width, fs.height,
              stats.render_seconds, cpu_s, stats.samples * 1e-6, stats.samples * 1e-6 / std::max(stats.render_seconds, 1e-9),
              a.output.c_str());
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand("render", "Render a dataset (or a built-in demo) to PNG or PFM: volume rendering and isosurfaces");
  cmd->add_option("dataset", a->dir, "dataset directory (or use --demo)");
  cmd->add_option("--demo", a->demo, "render a built-in demo instead (written to a temporary directory)")
      ->check(CLI::IsMember({"jet", "cosmo"}));
  cmd->add_option("--cells", a->cells, "demo size in cells")->capture_default_str();
  cmd->add_option("--field", a->field, "field to render (default: the first; demos: vorticity / density)");
  cmd->add_option("--step", a->step, "time step")->capture_default_str();
  cmd->add_option("--tf", a->tf,
                  "colour map: viridis, inferno, cool-warm, grayscale, blackbody, or a ParaView colour-map .json "
                  "(RGBPoints; its opacity Points are used when --opacity is not given)")
      ->capture_default_str();
  cmd->add_option("--range", a->range, "LO,HI value range of the transfer function (default: the field's range at the step)");
  cmd->add_flag("--log", a->log, "log10 value scale (a range reaching zero starts at HI*1e-6)");
  cmd->add_option("--opacity", a->opacity,
                  "opacity points VALUE:ALPHA,... with VALUE in data units (also with --log) and ALPHA the opacity "
                  "per unit distance; linear in between, constant outside (default: a ramp over the upper 90%)");
  cmd->add_option("--unit-distance", a->ref_step,
                  "world length over which ALPHA applies (default: 1/256 of the domain's largest extent)");
  cmd->add_option("--iso", a->iso, "isosurface values V[,V...] (at most 8), coloured by the transfer function");
  cmd->add_option("--iso-alpha", a->iso_alpha, "opacity of the isosurfaces")->capture_default_str();
  cmd->add_option("--color-field", a->color_field, "colour the isosurfaces by this field (its own range, same colour map)");
  cmd->add_option("--camera-pos", a->camera_pos, "X,Y,Z camera position, world units (default: fitted diagonal view)");
  cmd->add_option("--camera-at", a->camera_at, "X,Y,Z point looked at (default: the domain's centre)");
  cmd->add_option("--camera-up", a->camera_up, "X,Y,Z up direction")->default_str("0,1,0");
  cmd->add_option("--fov", a->fov, "vertical field of view, degrees")->capture_default_str();
  cmd->add_flag("--ortho", a->ortho, "orthographic projection (same framing as the perspective view at the look-at point)");
  cmd->add_option("--size", a->size, "image size WxH")->capture_default_str();
  cmd->add_option("--spp", a->spp, "rays per pixel")->capture_default_str();
  cmd->add_option("--rate", a->rate, "samples per cell width (of each ABR's finest level)")->capture_default_str();
  cmd->add_flag("--no-skip", a->no_skip, "no empty-space skipping (march every ABR)");
  cmd->add_flag("--no-adaptive", a->no_adaptive, "step at the dataset's finest cell width everywhere");
  cmd->add_flag("--no-jitter", a->no_jitter, "start every ray's samples at the same offset");
  cmd->add_flag("--shade", a->shade, "gradient shading of the volume (headlight)");
  cmd->add_flag("--stored-ranges", a->stored_ranges,
                "classify with the dataset's stored per-ABR ranges (per brick, looser) instead of tight ones");
  cmd->add_option("--background", a->background, "R,G,B background in [0,1] (sRGB)")->capture_default_str();
  cmd->add_flag("--alpha", a->alpha, "keep transparency (PNG RGBA; PFM: premultiplied RGB + OUT.alpha.pfm)");
  cmd->add_option("--device", a->device, "auto | cpu | cuda")->capture_default_str();
  cmd->add_option("-o,--output", a->output, "output image (.png or .pfm)")->required();
  add_block_render_options(cmd, a->blocks);
  cmd->callback([a] { run_render(*a); });
}

}  // namespace vs::cli
