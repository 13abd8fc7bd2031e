// `render --integrator blocks` and `render --optics blackbody`: the block raycaster of paper 004.
#include <cmath>
#include <cstdio>

#include "render_blocks.h"
#include "volstream/render/integrators/block_renderer.h"
#include "volstream/core/error.h"

namespace vs::cli {

void add_block_render_options(CLI::App* cmd, BlockRenderArgs& a) {
  cmd->add_option("--integrator", a.integrator, "abr: ABR tent integrator; blocks: kd-tree block raycaster (paper 004)")
      ->check(CLI::IsMember({"abr", "blocks"}))
      ->capture_default_str();
  cmd->add_option("--reconstruction", a.reconstruction, "blocks: nearest (cell value) or trilinear (between cell centres)")
      ->check(CLI::IsMember({"nearest", "trilinear"}))
      ->capture_default_str();
  cmd->add_option("--optics", a.optics,
                  "tf: transfer function; blackbody: emission of a blackbody at --temperature-field through Johnson "
                  "R,V,B filters scaled by density, Rayleigh absorption (implies --integrator blocks)")
      ->check(CLI::IsMember({"tf", "blackbody"}))
      ->capture_default_str();
  cmd->add_option("--temperature-field", a.temperature_field, "blackbody: temperature field (K)")->capture_default_str();
  cmd->add_option("--absorption", a.absorption, "blackbody: Rayleigh extinction (V band) per unit distance at max density")
      ->capture_default_str();
  cmd->add_option("--emission", a.emission, "blackbody: emission per unit distance at max density")->capture_default_str();
  cmd->add_option("--density-scale", a.density_scale,
                  "blackbody: how density is normalised: linear (rho / max rho, paper 004), log (its log10 position "
                  "over the value range, 7 decades below the max unless --range/--log give one) or auto (the transfer "
                  "function's scale: log for the cosmo demo's look and --log, else linear)")
      ->check(CLI::IsMember({"auto", "linear", "log"}))
      ->capture_default_str();
  cmd->add_option("--emission-power", a.emission_power,
                  "blackbody: emission ~ normalised density^P (default: 1 for a linear density scale, 4 for a log one)");
}

namespace {
// Decades of density below rho_max that the blackbody emission spans on a log scale; 0: linear.
float density_decades(const TransferFunctionSpec& spec, const std::string& scale) {
  const bool tf_log = spec.log_scale && spec.lo > 0.f && spec.hi > spec.lo;
  if (scale == "linear" || (scale == "auto" && !tf_log)) return 0.f;
  if (tf_log) return std::log10(spec.hi / spec.lo);
  if (!(spec.hi > 0.f)) throw UsageError("--density-scale log: the density range must reach above 0");
  return 7.f;
}
}  // namespace

Image render_with_blocks(const Dataset& ds, int step, int field, const TransferTable& tf,
                         const Camera& camera, const FrameSettings& fs, const BlockRenderArgs& a, FrameStats* stats) {
  if (!(a.absorption >= 0) || !(a.emission >= 0)) throw UsageError("--absorption and --emission must be >= 0");
  const bool bb = a.optics == "blackbody";
  const std::vector<float> values = ds.load_values(field, step);
  std::vector<float> temperature;
  if (bb) {
    const int tfield = ds.manifest().field_index(a.temperature_field);
    if (tfield < 0) throw UsageError("no temperature field '" + a.temperature_field + "' (--temperature-field)");
    temperature = ds.load_values(tfield, step);
  }
  BlockFrame frame;
  frame.width = fs.width;
  frame.height = fs.height;
  frame.settings.rate = fs.integrator.rate;
  frame.settings.ref_step = fs.integrator.ref_step;
  frame.settings.reconstruction = a.reconstruction == "nearest" ? Reconstruction::nearest : Reconstruction::trilinear;
  frame.settings.optics = bb ? Optics::blackbody : Optics::tf;
  const TransferFunctionSpec& spec = tf.spec();
  frame.blackbody.rho_max = spec.hi;
  frame.blackbody.log_decades = density_decades(spec, a.density_scale);
  frame.blackbody.emission_power = a.emission_power > 0 ? float(a.emission_power) : (frame.blackbody.log_decades > 0.f ? 4.f : 1.f);
  frame.blackbody.emission = float(a.emission);
  frame.blackbody.absorption = float(a.absorption);
  BlockRenderer renderer(ds.topology(), ds.manifest().transform);
  renderer.set_fields(values.data(), bb ? temperature.data() : nullptr,
                      frame.settings.reconstruction == Reconstruction::trilinear);
  const TfView view = tf.view();
  BlockStats bs;
  Image img = renderer.render(&view, camera, frame, a.device, &bs);
  std::printf("blocks: %zu blocks from %zu bricks, kd-tree %zu nodes built in %.3fs; %s (vertex values %.3fs), %s optics, %s\n",
              renderer.kd().blocks.size(), ds.topology().bricks.size(), renderer.kd().nodes.size(), bs.build_seconds,
              a.reconstruction.c_str(), renderer.vertex_seconds(), a.optics.c_str(), to_string(a.device));
  if (stats) {
    stats->device = a.device;
    stats->upload_seconds = bs.upload_seconds;
    stats->render_seconds = bs.render_seconds;
    stats->samples = bs.samples;
  }
  return img;
}

}  // namespace vs::cli
