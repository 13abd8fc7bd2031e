// How a dataset is shown when the caller does not say: the transfer function's range, colours
// and opacity, the built-in demos' looks, the colour field's table and the blackbody model's
// density scale. Library policy, shared by every caller (CLI, Python, viewer).
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "volstream/amr/model.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/io/dataset.h"
#include "volstream/render/camera.h"
#include "volstream/render/optics/blackbody.h"
#include "volstream/render/optics/transfer_function.h"

namespace vs {

// Built-in demos have a field and a look that show them well; other datasets: the first field
// in viridis.
struct Look {
  std::string field, color_map;
  float log_decades = 0;              // > 0: log scale over [hi / 10^decades, hi]
  std::vector<OpacityPoint> opacity;  // normalised positions; empty: default ramp
};
Look default_look(const DatasetManifest& manifest);

// The default camera for a dataset: its leaf cells' world box from a diagonal, fitted to the
// image's aspect ratio.
// The world box of the dataset's cells (AMR) or vertices (mesh).
Box3<double> world_bounds(const Dataset& dataset);
Camera default_view(const Dataset& dataset, uint32_t width, uint32_t height);

// A ParaView colour map JSON file (render/optics/transfer_function.h): a regular file of at most
// 64 MiB (not /dev/zero, a FIFO or a directory). InputError(path) on bad files.
ParaviewColorMap load_paraview_color_map(const std::string& path);

// The field index of `name`; UsageError naming the dataset when there is none.
int field_or_throw(const DatasetManifest& manifest, const std::string& name, const std::string& dataset_name);

// What a caller may say about a transfer function; everything else comes from the data.
struct TransferFunctionRequest {
  std::string color_map = "auto";  // a built-in map, a ParaView .json, or auto (the look's, else viridis)
  std::optional<Range> range;      // data units; default: the field's range over the range steps
  bool log = false;                // log10 scale (the demos' looks are log anyway under auto)
  std::vector<std::pair<double, double>> opacity;  // (value in data units, alpha); empty: look/preset/ramp
  // Instead of opacity points: `layers` narrow Gaussian layers over the range, each peaking at
  // layer_alpha (layer_opacity_points); 0: none.
  int layers = 0;
  double layer_alpha = 0.3;
};

// Opacity of n narrow Gaussian layers as yt's ColorTransferFunction.add_layers(n) places them,
// in the table's scale (log10 with log_scale): centres evenly spaced over [lo, hi] including both
// ends, each alpha * exp(-(x - c)^2 / w) with yt's default width w = 0.001 (hi - lo) / n (scale
// units), sampled at 15 points over +-4 sigma (zero at the outermost). Positions normalised as
// OpacityPoint's (0 at lo, 1 at hi; the end layers reach beyond).
std::vector<OpacityPoint> layer_opacity_points(const TransferFunctionSpec& spec, int n, double alpha);

// The union of a field's stored per-step ranges over `steps`.
Range union_range(const FieldInfo& field, const std::vector<int>& steps);

TransferFunctionSpec make_transfer_function(const DatasetManifest& manifest, int field,
                                            const std::vector<int>& range_steps,
                                            const TransferFunctionRequest& request);

// A colour field's table: the main table's colours over the colour field's own range.
TransferFunctionSpec make_color_field_transfer_function(const DatasetManifest& manifest, int color_field,
                                                        const std::vector<int>& range_steps,
                                                        const TransferFunctionSpec& main, bool log);

// The integrator when the caller does not choose one: paper 004's block raycaster for the
// blackbody optics on AMR data (the paper's pairing), else the ABRs (a mesh has its own walk).
IntegratorKind default_integrator(const Dataset& dataset, OpticsKind optics);

// How the blackbody model normalises density: linear (rho / rho_max, paper 004), log (its log10
// position, over the transfer function's decades or 7 below the max), or automatic (the
// transfer function's scale).
enum class DensityScale { automatic, linear, log };
DensityScale parse_density_scale(const std::string& name);  // auto|linear|log; UsageError otherwise

// emission_power <= 0: 1 on a linear scale, 4 on a log one. UsageError for negative coefficients.
BlackbodyParams make_blackbody_params(const TransferFunctionSpec& density_tf, DensityScale scale, double emission,
                                      double absorption, double emission_power);

}  // namespace vs
