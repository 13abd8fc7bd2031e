// The Python module `volstream`: the library's frame recipe (frame/frame_renderer.h) for
// notebooks and scripts, with names close to yt's. It binds the library, not the command line:
// the defaults (field, transfer function, camera) come from frame/look.h, so
// `volstream.create_scene(ds).render()` is the image `volstream render DATASET` writes.
//   ds = volstream.load(path) or volstream.demo("jet")      a dataset (docs/python.md): native, or
//                                                            converted as `volstream convert` does
//   ds.probe(field, points)                                  values at world points
//   sc = volstream.create_scene(ds); sc.render()             (H, W, 4) premultiplied linear RGBA
// Errors: InputError -> OSError("<file>: <what>"), UsageError -> ValueError(<what>), the lines
// the command line prints. Rendering and probing release the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "volstream/amr/demo.h"
#include "volstream/core/error.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/frame/look.h"
#include "volstream/io/dataset.h"
#include "volstream/io/image.h"
#include "volstream/io/import.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/umesh/demo.h"

namespace py = pybind11;
using vs::vec3d;

namespace {

using Vec3Tuple = std::array<double, 3>;
vec3d to_vec(const Vec3Tuple& a) { return vec3d(a[0], a[1], a[2]); }
py::tuple to_tuple(const vec3d& v) { return py::make_tuple(v.x, v.y, v.z); }

// A vector handed to numpy without a copy: the array's base is a capsule that owns it.
template <class T>
py::array_t<T> to_numpy(std::vector<T>&& values, const std::vector<py::ssize_t>& shape) {
  auto* heap = new std::vector<T>(std::move(values));
  py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, heap->data(), owner);
}

// A private temporary directory (mkdtemp: never a planted path or link).
std::filesystem::path make_temp_dir(const std::string& prefix) {
  std::string path = (std::filesystem::temp_directory_path() / (prefix + "XXXXXX")).string();
  if (!::mkdtemp(path.data()))
    vs::input_error(path, std::string("cannot create a temporary directory: ") + std::strerror(errno));
  return path;
}

// An open dataset; a demo's temporary directory goes with it.
struct DatasetHandle {
  std::filesystem::path temp_root;  // non-empty: removed when the handle is destroyed
  std::unique_ptr<vs::Dataset> dataset;
  std::mutex probe_mutex;
  std::unique_ptr<vs::FrameRenderer> prober;  // probe()'s renderer, made on first use
  DatasetHandle() = default;
  DatasetHandle(const DatasetHandle&) = delete;
  DatasetHandle& operator=(const DatasetHandle&) = delete;
  ~DatasetHandle() {
    prober.reset();
    dataset.reset();
    if (!temp_root.empty()) {
      std::error_code ec;
      std::filesystem::remove_all(temp_root, ec);
    }
  }
  const vs::DatasetManifest& manifest() const { return dataset->manifest(); }
  std::string name() const { return dataset->dir().string(); }
  int field(const std::string& name_or_empty) const {
    return name_or_empty.empty() ? 0 : vs::field_or_throw(manifest(), name_or_empty, name());
  }
  void check_step(int step) const {
    const int n = manifest().step_count();
    if (step < 0 || step >= n)
      throw vs::UsageError("step " + std::to_string(step) + " out of range 0.." + std::to_string(n - 1));
  }
  vs::Box3<double> domain() const { return vs::world_bounds(*dataset); }
};
using DatasetPtr = std::shared_ptr<DatasetHandle>;

// A dataset converted into a private temporary directory by `convert(dir)`, then opened; the
// directory is removed with the handle (also when the conversion fails).
template <class Convert>
DatasetPtr convert_to_temp(const std::string& name, const Convert& convert) {
  auto h = std::make_shared<DatasetHandle>();
  py::gil_scoped_release release;
  h->temp_root = make_temp_dir("volstream_python_" + name + "_");
  const std::filesystem::path dir = h->temp_root / "dataset";
  convert(dir);
  h->dataset = std::make_unique<vs::Dataset>(dir);
  return h;
}

// One path (str or os.PathLike) or a sequence of them.
std::vector<std::filesystem::path> paths_of(const py::object& path) {
  const py::object fspath = py::module_::import("os").attr("fspath");
  std::vector<std::filesystem::path> paths;
  if (py::isinstance<py::str>(path) || py::hasattr(path, "__fspath__"))
    paths.push_back(fspath(path).cast<std::string>());
  else
    for (const py::handle& p : path) paths.push_back(fspath(p).cast<std::string>());
  if (paths.empty()) throw vs::UsageError("load needs a path");
  return paths;
}

bool is_native_dataset(const std::filesystem::path& path) {
  std::error_code ec;
  return std::filesystem::is_directory(path, ec) && std::filesystem::exists(path / vs::dataset_files::kManifest, ec);
}

// How a converted mesh is stored: paper 002's compact encoding (the default, as `volstream
// convert`'s) or the reference one.
vs::MeshEncoding stored_encoding(const std::string& name) {
  if (name != "compact" && name != "reference")
    throw vs::UsageError("encoding must be 'compact' or 'reference', not '" + name + "'");
  return vs::parse_mesh_encoding(name);
}

DatasetPtr load(const py::object& path, const std::string& format, const std::optional<std::array<int, 3>>& dims,
                const std::string& type, bool big_endian, const Vec3Tuple& origin, const Vec3Tuple& spacing,
                bool series, const std::string& field, const std::map<std::string, std::string>& scalars,
                const std::vector<std::string>& fields, const std::string& encoding, bool split_into_tets,
                const std::vector<std::string>& regions) {
  vs::ImportRequest in;
  in.inputs = paths_of(path);
  // A native dataset is opened where it is; anything else is converted (a missing path too, so
  // that its error is the importer's "<path>: does not exist").
  if (in.inputs.size() == 1 && format == "auto" && is_native_dataset(in.inputs[0])) {
    if (!fields.empty()) throw vs::UsageError("fields= selects what a conversion keeps; this is a dataset already");
    auto h = std::make_shared<DatasetHandle>();
    py::gil_scoped_release release;
    h->dataset = std::make_unique<vs::Dataset>(in.inputs[0]);
    return h;
  }
  in.format = format;
  if (dims) in.dims.assign(dims->begin(), dims->end());
  in.raw_type = type;
  in.big_endian = big_endian;
  in.origin.assign(origin.begin(), origin.end());
  in.spacing.assign(spacing.begin(), spacing.end());
  in.series = series;
  in.field_name = field;
  for (const auto& [name, file] : scalars) in.scalars.push_back({name, file});
  in.regions = regions;
  vs::ConvertOptions options = vs::ConvertOptions::silent();
  options.fields = fields;
  options.mesh_encoding = stored_encoding(encoding);
  options.split_into_tets = split_into_tets;
  vs::import_format(in);  // what cannot be converted fails here, before a temporary directory exists
  return convert_to_temp("load", [&](const std::filesystem::path& dir) { vs::import_to_dataset(in, dir, options); });
}

DatasetPtr demo(const std::string& name, double cells, int steps, double elements, const std::string& encoding,
                bool split_into_tets) {
  if (steps < 1 || steps > 1000) throw vs::UsageError("demo steps must be in [1, 1000]");
  if (vs::is_mesh_demo(name)) {
    if (!(elements >= 6 && elements <= 5e8)) throw vs::UsageError("demo elements must be in [6, 5e8]");
    const vs::MeshDemoOptions o{name, uint64_t(elements), steps};
    vs::check_mesh_demo(o);
    vs::ConvertOptions options = vs::ConvertOptions::silent();
    options.mesh_encoding = stored_encoding(encoding);
    options.split_into_tets = split_into_tets;
    return convert_to_temp(name, [&](const std::filesystem::path& dir) {
      auto series = vs::make_mesh_demo_series(o);
      vs::convert_mesh_to_dataset(*series, dir, options);
    });
  }
  if (split_into_tets) throw vs::UsageError("split_into_tets applies to mesh demos");
  if (!(cells >= 1e4 && cells <= 2e9)) throw vs::UsageError("demo cells must be in [1e4, 2e9]");
  auto source = vs::make_demo({name, uint64_t(cells), steps});  // UsageError for an unknown name
  return convert_to_temp(name, [&](const std::filesystem::path& dir) {
    vs::convert_to_dataset(*source, dir, vs::ConvertOptions::silent());
  });
}

py::array probe(DatasetHandle& h, const std::optional<std::string>& field_name,
                const py::array_t<double, py::array::c_style | py::array::forcecast>& points, int step,
                bool brute_force, const std::string& device) {
  const int field = h.field(field_name.value_or(""));
  h.check_step(step);
  if (points.ndim() != 2 || points.shape(1) != 3) throw vs::UsageError("points must be an (N, 3) array");
  const size_t n = size_t(points.shape(0));
  std::vector<vec3d> world(n);
  const double* p = points.data();
  for (size_t i = 0; i < n; ++i) world[i] = vec3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
  const vs::Device dev = vs::resolve_device(device);
  if (brute_force) {
    std::vector<double> v;
    {
      py::gil_scoped_release release;
      v = vs::probe_brute_force(*h.dataset, field, step, world);
    }
    return to_numpy(std::move(v), {py::ssize_t(n)});
  }
  std::vector<float> v;
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(h.probe_mutex);
    if (!h.prober || h.prober->device() != dev) {
      h.prober.reset();
      h.prober = std::make_unique<vs::FrameRenderer>(*h.dataset, dev);
    }
    v = h.prober->probe(field, step, world);
  }
  return to_numpy(std::move(v), {py::ssize_t(n)});
}

// What a scene shows; the camera and transfer function objects are views of it.
struct SceneState {
  DatasetPtr ds;
  vs::Device device = vs::Device::cpu;
  int field = 0, step = 0;
  // Camera: unset parts come from default_view for the resolution (as `volstream render`).
  std::optional<vec3d> position, focus, up;
  double fov = 35;
  bool ortho = false;
  uint32_t width = 512, height = 512;
  vs::TransferFunctionRequest tf;
  vs::IntegratorSettings integrator;
  std::vector<double> iso;
  std::optional<vs::IntegratorKind> kind;  // unset: the library's default for the optics (look.h)
  std::optional<int> color_field;          // isosurfaces coloured by this field (tf optics)
  vs::OpticsKind optics = vs::OpticsKind::tf;
  std::string temperature_field = "temperature";  // blackbody
  // Blackbody model (`volstream render --optics blackbody`'s defaults).
  vs::DensityScale density_scale = vs::DensityScale::automatic;
  double emission = 4, absorption = 0.25, emission_power = 0;
  vec3d background{0.06, 0.06, 0.08};
  std::mutex render_mutex;
  std::unique_ptr<vs::FrameRenderer> renderer;  // after ds: destroyed before it

  SceneState() { integrator.ref_step = 0; }  // 0: the renderer's default, 1/256 of the domain

  vs::Camera camera() const {
    vs::Camera c = vs::default_view(*ds->dataset, width, height);
    if (focus) c.look_at = *focus;
    if (position) c.position = *position;
    if (up) c.up = *up;
    c.fov_deg = fov;
    c.ortho = ortho;
    return c;
  }
  vs::TransferFunctionSpec transfer_function(const vs::TransferFunctionRequest& request) const {
    return vs::make_transfer_function(ds->manifest(), field, {step}, request);
  }
  vs::FrameRequest request() const {
    vs::FrameRequest r;
    r.step = step;
    r.field = field;
    r.width = width;
    r.height = height;
    r.camera = camera();
    vs::make_camera_view(r.camera, width, height);  // UsageError for a degenerate camera
    r.tf = transfer_function(tf);
    r.integrator = integrator;
    r.integrator.iso_count = uint32_t(iso.size());
    for (size_t i = 0; i < iso.size(); ++i) r.integrator.iso[i] = float(iso[i]);
    r.kind = kind.value_or(vs::default_integrator(*ds->dataset, optics));
    if (optics == vs::OpticsKind::blackbody) {
      if (color_field)
        throw vs::UsageError("color_field: not with optics 'blackbody' (the second field is the temperature)");
      r.optics = optics;
      r.second_field = vs::field_or_throw(ds->manifest(), temperature_field, ds->name());
      r.blackbody = vs::make_blackbody_params(r.tf, density_scale, emission, absorption, emission_power);
    } else if (color_field) {
      r.second_field = *color_field;
      r.color_tf = vs::make_color_field_transfer_function(ds->manifest(), *color_field, {step}, r.tf, tf.log);
    }
    return r;
  }
  vs::Image render() {
    const vs::FrameRequest r = request();
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(render_mutex);
    if (!renderer) renderer = std::make_unique<vs::FrameRenderer>(*ds->dataset, device);
    return renderer->render(r);
  }
  vs::ImageWriteOptions write_options(const std::optional<Vec3Tuple>& bg, bool alpha) const {
    vs::ImageWriteOptions o;
    o.alpha = alpha;
    o.background = vs::vec3f(bg ? to_vec(*bg) : background);
    return o;
  }
};
using ScenePtr = std::shared_ptr<SceneState>;

struct CameraRef {
  ScenePtr s;
};

// Opacity points are kept in data units; the renderer interpolates them linearly in the transfer
// function's scale (log10 of the value when log, else the value), so the Gaussians are built and
// summed there.
double to_scale(double value, bool log) { return log ? std::log10(value) : value; }
double from_scale(double t, bool log) { return log ? std::pow(10.0, t) : t; }

// Piecewise-linear alpha of points sorted by t, constant outside them (as the table is baked);
// 0 without points.
double alpha_at(const std::vector<std::pair<double, double>>& points, double t) {
  if (points.empty()) return 0;
  if (t <= points.front().first) return points.front().second;
  if (t >= points.back().first) return points.back().second;
  const auto hi = std::upper_bound(points.begin(), points.end(), t,
                                   [](double x, const std::pair<double, double>& p) { return x < p.first; });
  const auto lo = hi - 1;
  const double f = (t - lo->first) / (hi->first - lo->first);
  return lo->second + (hi->second - lo->second) * f;
}

// yt's TransferFunction.add_gaussian: `opacity` (data units) plus alpha * exp(-(t - c)^2 / width)
// of the scale t, c = center in that scale (width in scale units squared, as yt's). The Gaussian
// is sampled at 17 points over +-4 standard deviations, zero at both ends, and added to the old
// points' piecewise-linear alpha at every old and new point (clamped to 1; no points: from zero,
// not the default ramp).
std::vector<std::pair<double, double>> add_gaussian(const std::vector<std::pair<double, double>>& opacity,
                                                    double center, double width, double alpha, bool log) {
  if (!std::isfinite(center) || (log && !(center > 0)))
    throw vs::UsageError("gaussian center must be finite (and > 0 with log)");
  if (!(width > 0 && std::isfinite(width))) throw vs::UsageError("gaussian width must be finite and > 0");
  if (!(alpha >= 0 && alpha <= 1)) throw vs::UsageError("gaussian alpha must be in [0, 1]");
  std::vector<std::pair<double, double>> old, gauss;
  for (const auto& [v, a] : opacity) old.push_back({to_scale(v, log), a});
  std::sort(old.begin(), old.end());
  const double c = to_scale(center, log), sigma = std::sqrt(width / 2);
  constexpr int kHalf = 8;  // samples each side: every sigma / 2
  for (int k = -kHalf; k <= kHalf; ++k) {
    const double t = c + sigma * k / 2;
    gauss.push_back({t, std::abs(k) == kHalf ? 0.0 : alpha * std::exp(-(t - c) * (t - c) / width)});
  }
  std::vector<double> ts;
  for (const auto& p : old) ts.push_back(p.first);
  for (const auto& p : gauss) ts.push_back(p.first);
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end()), ts.end());
  std::vector<std::pair<double, double>> sum;
  for (double t : ts) {
    const double g = t < gauss.front().first || t > gauss.back().first ? 0.0 : alpha_at(gauss, t);
    sum.push_back({from_scale(t, log), std::min(1.0, alpha_at(old, t) + g)});
  }
  return sum;
}
struct TransferFunctionRef {
  ScenePtr s;
  // Checks a changed request against the data now (bad colour map, range, opacity) and keeps it.
  void update(const vs::TransferFunctionRequest& r) {
    s->transfer_function(r);
    s->tf = r;
  }
};

ScenePtr create_scene(const DatasetPtr& ds, const std::optional<std::string>& field, bool log,
                      const std::string& device) {
  auto s = std::make_shared<SceneState>();
  s->ds = ds;
  const std::string f = field ? *field : vs::default_look(ds->manifest()).field;
  s->field = vs::field_or_throw(ds->manifest(), f, ds->name());
  s->tf.log = log;
  s->transfer_function(s->tf);
  s->device = vs::resolve_device(device);
  return s;
}

py::array image_array(vs::Image&& img) {
  const py::ssize_t h = img.height, w = img.width;
  return to_numpy(std::move(img.rgba), {h, w, 4});
}

void save(SceneState& s, const std::string& path, const std::optional<Vec3Tuple>& background, bool alpha) {
  vs::check_image_output(path);
  const vs::ImageWriteOptions o = s.write_options(background, alpha);
  const vs::Image img = s.render();
  py::gil_scoped_release release;
  vs::write_image(img, path, o);
}

py::bytes repr_png(SceneState& s) {
  const vs::ImageWriteOptions o = s.write_options(std::nullopt, false);
  const vs::Image img = s.render();
  std::string bytes;
  {
    py::gil_scoped_release release;
    const std::filesystem::path dir = make_temp_dir("volstream_png_");
    const std::filesystem::path file = dir / "image.png";
    try {
      vs::write_png(img, file.string(), o);
      std::ifstream in(file, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    } catch (...) {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
      throw;
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
  return py::bytes(bytes);
}

vec3d finite_vec(const Vec3Tuple& a, const char* what) {
  for (double v : a)
    if (!std::isfinite(v)) throw vs::UsageError(std::string(what) + " must be finite");
  return to_vec(a);
}

}  // namespace

PYBIND11_MODULE(volstream, m) {
  m.doc() =
      "volstream: volume rendering of AMR data and unstructured meshes (ABRs, empty-space skipping,\n"
      "isosurfaces).\n\n"
      "    ds = volstream.load('dataset_dir')   # or a plotfile, .vtu, ...; volstream.demo('jet')\n"
      "    sc = volstream.create_scene(ds)\n"
      "    img = sc.render()                    # (H, W, 4) float32 premultiplied linear RGBA\n"
      "    sc.save('frame.png')\n\n"
      "Bad files raise OSError('<file>: <what>'), bad values ValueError.";

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const vs::InputError& e) {
      PyErr_SetString(PyExc_OSError, (e.file() + ": " + e.what()).c_str());
    } catch (const vs::UsageError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  py::class_<DatasetHandle, DatasetPtr>(m, "Dataset",
                                        "An open dataset, AMR or mesh (volstream.load or volstream.demo).")
      .def_property_readonly("path", &DatasetHandle::name, "The dataset directory.")
      .def_property_readonly(
          "fields",
          [](const DatasetHandle& h) {
            std::vector<std::string> names;
            for (const auto& f : h.manifest().fields) names.push_back(f.name);
            return names;
          },
          "Field names, in the dataset's order.")
      .def_property_readonly(
          "steps",
          [](const DatasetHandle& h) {
            std::vector<int> s(size_t(h.manifest().step_count()));
            for (size_t i = 0; i < s.size(); ++i) s[i] = int(i);
            return s;
          },
          "Time step indices 0 .. n-1.")
      .def_property_readonly(
          "times", [](const DatasetHandle& h) { return h.manifest().step_times; }, "Simulation time of each step.")
      .def_property_readonly(
          "domain",
          [](const DatasetHandle& h) {
            const auto b = h.domain();
            return std::make_pair(to_tuple(b.lower), to_tuple(b.upper));
          },
          "World box of the leaf cells (AMR) or vertices (mesh): ((x0, y0, z0), (x1, y1, z1)).")
      .def_property_readonly(
          "domain_left_edge", [](const DatasetHandle& h) { return to_tuple(h.domain().lower); },
          "Lower world corner of the domain.")
      .def_property_readonly(
          "domain_right_edge", [](const DatasetHandle& h) { return to_tuple(h.domain().upper); },
          "Upper world corner of the domain.")
      .def_property_readonly(
          "domain_center", [](const DatasetHandle& h) { return to_tuple(h.domain().center()); },
          "Centre of the world box.")
      .def_property_readonly(
          "kind", [](const DatasetHandle& h) { return std::string(h.dataset->is_mesh() ? "mesh" : "amr"); },
          "'amr' (cells in bricks) or 'mesh' (an unstructured mesh: values at its vertices).")
      .def_property_readonly(
          "cell_count",
          [](const DatasetHandle& h) {
            return h.dataset->is_mesh() ? std::nullopt : std::optional<uint64_t>(h.manifest().cell_count);
          },
          "Number of leaf cells (AMR); None for a mesh.")
      .def_property_readonly(
          "element_count",
          [](const DatasetHandle& h) {
            return h.dataset->is_mesh() ? std::optional<uint64_t>(h.manifest().mesh.elements) : std::nullopt;
          },
          "Number of mesh elements (tetrahedra, pyramids, wedges, hexahedra); None for AMR.")
      .def_property_readonly(
          "vertex_count",
          [](const DatasetHandle& h) {
            return h.dataset->is_mesh() ? std::optional<uint64_t>(h.manifest().mesh.vertices) : std::nullopt;
          },
          "Number of mesh vertices (one value per vertex and field); None for AMR.")
      .def(
          "field_range",
          [](const DatasetHandle& h, const std::string& field, int step) {
            h.check_step(step);
            const vs::Range r = h.manifest().fields[size_t(h.field(field))].step_ranges[size_t(step)];
            return std::make_pair(double(r.lo), double(r.hi));
          },
          py::arg("field"), py::arg("step") = 0, "(min, max) of a field at a step, from the manifest.")
      .def("probe", &probe, py::arg("field"), py::arg("points"), py::arg("step") = 0, py::arg("brute_force") = false,
           py::arg("device") = "cpu",
           "Values of `field` (None: the first) at world points, an (N, 3) array, NaN outside the data.\n"
           "Through the ABRs or the mesh's BVH (float32, as `volstream probe`), or with brute_force=True\n"
           "the tent-basis sum over every cell or a search of every mesh element (float64, the reference).\n"
           "device: cpu | cuda | auto.")
      .def("__repr__", [](const DatasetHandle& h) {
        const vs::DatasetManifest& manifest = h.manifest();
        const std::string size = h.dataset->is_mesh() ? std::to_string(manifest.mesh.elements) + " elements, " +
                                                            std::to_string(manifest.mesh.vertices) + " vertices"
                                                      : std::to_string(manifest.cell_count) + " cells";
        return "<volstream.Dataset '" + h.name() + "': " + size + ", " + std::to_string(manifest.fields.size()) +
               " fields, " + std::to_string(manifest.step_count()) + " steps>";
      });

  m.def("load", &load, py::arg("path"), py::kw_only(), py::arg("format") = "auto", py::arg("dims") = py::none(),
        py::arg("type") = "float32", py::arg("big_endian") = false, py::arg("origin") = Vec3Tuple{0, 0, 0},
        py::arg("spacing") = Vec3Tuple{1, 1, 1}, py::arg("series") = false, py::arg("field") = "scalar",
        py::arg("scalars") = std::map<std::string, std::string>{}, py::arg("fields") = std::vector<std::string>{},
        py::arg("encoding") = "compact", py::arg("split_into_tets") = false,
        py::arg("regions") = std::vector<std::string>{},
        "Open a native dataset directory (written by `volstream convert` or `volstream demo`), or convert\n"
        "what `volstream convert` takes into a private temporary dataset, removed when the Dataset is\n"
        "garbage-collected: an AMReX plotfile directory (a list of them: time steps), [cells, scalars...]\n"
        "of ExaBrick, raw grids (dims=(X, Y, Z), type=, big_endian=, origin=, spacing=; several files are\n"
        "fields, or steps with series=True, named by field=), meshes (.vtu, .pvtu, .vtm, .vtk, .pvd,\n"
        ".series, .ugrid, EnSight .case, Exodus II .exo, .cgns, Gmsh .msh, Fluent .cas with its .dat files; a list:\n"
        "time steps) with scalars={'name': 'file.f32'} "
        "for "
        "UGRID. format: auto "
        "|\n"
        "plotfile | exabrick | raw\n"
        "| mesh; fields: keep only these; encoding: how a converted mesh is stored, 'compact' (paper 002's\n"
        "encoding, as `volstream convert`) or 'reference'; split_into_tets: store a mesh's pyramids, wedges\n"
        "and hexahedra as tets (convert --split-into-tets); regions: an OpenFOAM case's regions, a Fluent\n"
        "case's cell zones, an Exodus file's element blocks, a CGNS file's zones, a Gmsh file's physical\n"
        "groups of volumes, an EnSight case's parts or a .vtm's blocks to read (convert --region; default:\n"
        "all).\n"
        "OSError('<file>: <what>') for a missing or damaged input.");
  m.def("demo", &demo, py::arg("name"), py::arg("cells") = 1e5, py::arg("steps") = 2, py::arg("elements") = 1e5,
        py::arg("encoding") = "compact", py::arg("split_into_tets") = false,
        "A built-in demo, AMR ('jet' or 'cosmo', about `cells` leaf cells) or a mesh ('tets', 'mixed' or\n"
        "'holes', about `elements` elements, stored in `encoding`: 'compact' or 'reference'), of `steps`\n"
        "time steps, written to a private temporary directory that is removed when the Dataset is\n"
        "garbage-collected. split_into_tets: a mesh's other elements stored as tets.");

  py::class_<CameraRef>(m, "Camera",
                        "The scene's camera. Unset position, focus and up come from the default view fitted to\n"
                        "the resolution (as `volstream render`).")
      .def_property(
          "position", [](const CameraRef& c) { return to_tuple(c.s->camera().position); },
          [](CameraRef& c, const Vec3Tuple& v) { c.s->position = finite_vec(v, "camera position"); },
          "Eye position (world units).")
      .def_property(
          "focus", [](const CameraRef& c) { return to_tuple(c.s->camera().look_at); },
          [](CameraRef& c, const Vec3Tuple& v) { c.s->focus = finite_vec(v, "camera focus"); },
          "Point looked at (world units).")
      .def_property(
          "up", [](const CameraRef& c) { return to_tuple(c.s->camera().up); },
          [](CameraRef& c, const Vec3Tuple& v) { c.s->up = finite_vec(v, "camera up"); }, "Up direction.")
      .def_property(
          "fov", [](const CameraRef& c) { return c.s->fov; },
          [](CameraRef& c, double v) {
            if (!(v > 0 && v < 180)) throw vs::UsageError("fov must be in (0, 180)");
            c.s->fov = v;
          },
          "Vertical field of view, degrees.")
      .def_property(
          "ortho", [](const CameraRef& c) { return c.s->ortho; }, [](CameraRef& c, bool v) { c.s->ortho = v; },
          "Orthographic projection (same framing as the perspective view at the focus).")
      .def_property(
          "resolution", [](const CameraRef& c) { return py::make_tuple(c.s->width, c.s->height); },
          [](CameraRef& c, const std::pair<double, double>& wh) {
            const double w = wh.first, h = wh.second;
            if (!(w >= 1 && h >= 1 && w <= 16384 && h <= 16384 && w == std::floor(w) && h == std::floor(h) &&
                  w * h <= 8192.0 * 8192.0))
              throw vs::UsageError("resolution expects (W, H) with 1 <= W, H <= 16384 and W*H <= 8192*8192");
            c.s->width = uint32_t(w);
            c.s->height = uint32_t(h);
          },
          "Image size (W, H) in pixels.")
      .def(
          "reset",
          [](CameraRef& c) {
            c.s->position.reset();
            c.s->focus.reset();
            c.s->up.reset();
            c.s->fov = 35;
            c.s->ortho = false;
          },
          "Back to the default view (resolution unchanged).");

  py::class_<TransferFunctionRef>(m, "TransferFunction",
                                  "The scene's transfer function: colour map, value bounds, scale and opacity.\n"
                                  "Unset parts come from the library's look for the dataset (frame/look.h).")
      .def_property(
          "cmap", [](const TransferFunctionRef& t) { return t.s->tf.color_map; },
          [](TransferFunctionRef& t, const std::string& name) {
            auto r = t.s->tf;
            r.color_map = name;
            t.update(r);
          },
          "auto (the look's, else viridis), viridis, inferno, cool-warm, grayscale, blackbody, or a ParaView\n"
          ".json file.")
      .def_property(
          "log", [](const TransferFunctionRef& t) { return t.s->tf.log; },
          [](TransferFunctionRef& t, bool v) {
            auto r = t.s->tf;
            r.log = v;
            t.update(r);
          },
          "log10 value scale.")
      .def_property_readonly(
          "bounds",
          [](const TransferFunctionRef& t) {
            const auto spec = t.s->transfer_function(t.s->tf);
            return std::make_pair(double(spec.lo), double(spec.hi));
          },
          "(lo, hi) in data units: set_bounds's, else the field's range at the step.")
      .def(
          "set_bounds",
          [](TransferFunctionRef& t, std::optional<std::pair<double, double>> b) {
            auto r = t.s->tf;
            if (b) {
              if (!(std::isfinite(b->first) && std::isfinite(b->second) && b->first < b->second))
                throw vs::UsageError("bounds expect (lo, hi) with lo < hi");
              r.range = vs::Range{float(b->first), float(b->second)};
            } else {
              r.range.reset();
            }
            t.update(r);
          },
          py::arg("bounds"), "Value range (lo, hi) in data units; None: the field's range.")
      .def_property_readonly(
          "opacity", [](const TransferFunctionRef& t) { return t.s->tf.opacity; },
          "Opacity points [(value, alpha), ...]; empty: the look's or the default ramp.")
      .def(
          "set_opacity",
          [](TransferFunctionRef& t, const std::vector<std::pair<double, double>>& points) {
            for (const auto& [v, a] : points)
              if (!std::isfinite(v) || !(a >= 0 && std::isfinite(a)))
                throw vs::UsageError("opacity points expect finite (value, alpha) with alpha >= 0");
            auto r = t.s->tf;
            r.opacity = points;
            t.update(r);
          },
          py::arg("points"),
          "Opacity points [(value, alpha), ...], value in data units (also with log), alpha per unit\n"
          "distance; linear in between, constant outside. [] restores the default.")
      .def(
          "add_gaussian",
          [](TransferFunctionRef& t, double center, double width, double alpha) {
            auto r = t.s->tf;
            r.opacity = add_gaussian(r.opacity, center, width, alpha, r.log);
            t.update(r);
          },
          py::arg("center"), py::arg("width"), py::arg("alpha"),
          "Add alpha * exp(-(t - c)^2 / width) to the opacity, as yt's add_gaussian: t is the scale (log10\n"
          "of the value with log, else the value), c the scale of `center` (data units), width in scale\n"
          "units squared (standard deviation sqrt(width / 2)). Sampled as 17 opacity points over +-4\n"
          "standard deviations (zero at both ends) and added to the current points (none: from zero, not\n"
          "the default ramp), clamped to 1.")
      .def(
          "add_layers",
          [](TransferFunctionRef& t, int n, std::optional<double> w, const py::object& alpha, std::optional<double> mi,
             std::optional<double> ma) {
            if (n < 1 || n > 1000) throw vs::UsageError("add_layers: n must be in [1, 1000]");
            auto r = t.s->tf;
            const vs::TransferFunctionSpec spec = t.s->transfer_function(r);
            const double lo = to_scale(mi.value_or(spec.lo), r.log), hi = to_scale(ma.value_or(spec.hi), r.log);
            if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi))
              throw vs::UsageError("add_layers: needs mi < ma (> 0 with log)");
            // yt's default width, 0.001 * span / n, for a unit span; scaled with the span squared
            // so that the layers are as wide, relative to the range, on any range.
            const double width = w.value_or(0.001 * (hi - lo) * (hi - lo) / n);
            std::vector<double> alphas(static_cast<size_t>(n));
            for (int i = 0; i < n; ++i)
              alphas[size_t(i)] = std::pow(10.0, n == 1 ? -3.0 : -3.0 + 3.0 * i / (n - 1));  // numpy.logspace(-3, 0, n)
            if (!alpha.is_none()) {
              if (py::isinstance<py::float_>(alpha) || py::isinstance<py::int_>(alpha))
                std::fill(alphas.begin(), alphas.end(), alpha.cast<double>());
              else
                alphas = alpha.cast<std::vector<double>>();
              if (alphas.size() != size_t(n)) throw vs::UsageError("add_layers: alpha needs n values");
            }
            for (int i = 0; i < n; ++i) {
              const double c = n == 1 ? lo : lo + (hi - lo) * i / (n - 1);
              r.opacity = add_gaussian(r.opacity, from_scale(c, r.log), width, alphas[size_t(i)], r.log);
            }
            t.update(r);
          },
          py::arg("n"), py::arg("w") = py::none(), py::kw_only(), py::arg("alpha") = py::none(),
          py::arg("mi") = py::none(), py::arg("ma") = py::none(),
          "As yt's ColorTransferFunction.add_layers: n Gaussians (add_gaussian) at evenly spaced positions\n"
          "from mi to ma inclusive (data units; default: the bounds), evenly in log10 with log; width w\n"
          "(scale units squared; default 0.001 * span^2 / n, span = ma - mi in the scale); alpha: one value\n"
          "or n values (default: n values from 1e-3 to 1, evenly in log, as yt's). Colours stay the\n"
          "colour map's.");

  py::class_<SceneState, ScenePtr>(m, "Scene", "What to render of a dataset and how (volstream.create_scene).")
      .def_property_readonly(
          "camera", [](const ScenePtr& s) { return CameraRef{s}; }, "The camera (a view of this scene).")
      .def_property_readonly(
          "transfer_function", [](const ScenePtr& s) { return TransferFunctionRef{s}; },
          "The transfer function (a view of this scene).")
      .def_property_readonly(
          "dataset", [](const SceneState& s) { return s.ds; }, "The dataset shown.")
      .def_property(
          "field", [](const SceneState& s) { return s.ds->manifest().fields[size_t(s.field)].name; },
          [](SceneState& s, const std::string& name) {
            s.field = vs::field_or_throw(s.ds->manifest(), name, s.ds->name());
          },
          "The field rendered.")
      .def_property(
          "step", [](const SceneState& s) { return s.step; },
          [](SceneState& s, int step) {
            s.ds->check_step(step);
            s.step = step;
          },
          "The time step rendered.")
      .def_property(
          "iso", [](const SceneState& s) { return s.iso; },
          [](SceneState& s, const std::vector<double>& values) {
            if (values.size() > vs::kMaxIso)
              throw vs::UsageError("iso takes at most " + std::to_string(vs::kMaxIso) + " values");
            for (double v : values)
              if (!std::isfinite(v)) throw vs::UsageError("iso values must be finite");
            s.iso = values;
          },
          "Isosurface values (at most 8), coloured by the transfer function.")
      .def_property(
          "iso_alpha", [](const SceneState& s) { return s.integrator.iso_alpha; },
          [](SceneState& s, double v) {
            if (!(v >= 0 && v <= 1)) throw vs::UsageError("iso_alpha must be in [0, 1]");
            s.integrator.iso_alpha = float(v);
          },
          "Opacity of the isosurfaces.")
      .def_property(
          "integrator",
          [](const SceneState& s) {
            if (!s.kind) return std::string("auto");
            return std::string(*s.kind == vs::IntegratorKind::abr ? "abr" : "blocks");
          },
          [](SceneState& s, const std::string& name) {
            if (name == "auto")
              s.kind.reset();
            else if (name == "abr")
              s.kind = vs::IntegratorKind::abr;
            else if (name == "blocks")
              s.kind = vs::IntegratorKind::blocks;
            else
              throw vs::UsageError("integrator must be 'auto', 'abr' or 'blocks', not '" + name + "'");
          },
          "abr: ABRs with empty-space skipping (meshes: their element walk); blocks: the kd-tree block\n"
          "raycaster (trilinear); auto (default, as `volstream render`): blocks for the blackbody optics on\n"
          "AMR data, else abr.")
      .def_property(
          "optics",
          [](const SceneState& s) { return std::string(s.optics == vs::OpticsKind::tf ? "tf" : "blackbody"); },
          [](SceneState& s, const std::string& name) {
            if (name == "tf")
              s.optics = vs::OpticsKind::tf;
            else if (name == "blackbody")
              s.optics = vs::OpticsKind::blackbody;
            else
              throw vs::UsageError("optics must be 'tf' or 'blackbody', not '" + name + "'");
          },
          "tf: the transfer function; blackbody: emission of a blackbody at `temperature_field` through\n"
          "Rayleigh extinction, the field rendered being the density (`volstream render --optics blackbody`).")
      .def_property(
          "temperature_field", [](const SceneState& s) { return s.temperature_field; },
          [](SceneState& s, const std::string& name) {
            vs::field_or_throw(s.ds->manifest(), name, s.ds->name());
            s.temperature_field = name;
          },
          "Blackbody optics: the temperature field (K).")
      .def_property(
          "emission", [](const SceneState& s) { return s.emission; },
          [](SceneState& s, double v) {
            if (!(v >= 0 && std::isfinite(v))) throw vs::UsageError("emission must be finite and >= 0");
            s.emission = v;
          },
          "Blackbody optics: emission per unit distance at the maximum density.")
      .def_property(
          "absorption", [](const SceneState& s) { return s.absorption; },
          [](SceneState& s, double v) {
            if (!(v >= 0 && std::isfinite(v))) throw vs::UsageError("absorption must be finite and >= 0");
            s.absorption = v;
          },
          "Blackbody optics: Rayleigh extinction (V band) per unit distance at the maximum density.")
      .def_property(
          "density_scale",
          [](const SceneState& s) {
            switch (s.density_scale) {
              case vs::DensityScale::linear:
                return std::string("linear");
              case vs::DensityScale::log:
                return std::string("log");
              default:
                return std::string("auto");
            }
          },
          [](SceneState& s, const std::string& name) { s.density_scale = vs::parse_density_scale(name); },
          "Blackbody optics: density normalised linearly, by its log10 position, or auto (the transfer\n"
          "function's scale).")
      .def_property(
          "color_field",
          [](const SceneState& s) {
            return s.color_field ? std::optional<std::string>(s.ds->manifest().fields[size_t(*s.color_field)].name)
                                 : std::nullopt;
          },
          [](SceneState& s, const std::optional<std::string>& name) {
            s.color_field =
                name ? std::optional<int>(vs::field_or_throw(s.ds->manifest(), *name, s.ds->name())) : std::nullopt;
          },
          "Colour the isosurfaces by this field (the transfer function's colours over its range at the\n"
          "step); None: by the rendered field.")
      .def_property(
          "rate", [](const SceneState& s) { return s.integrator.rate; },
          [](SceneState& s, double v) {
            if (!(v > 0 && v <= 64)) throw vs::UsageError("rate must be in (0, 64]");
            s.integrator.rate = float(v);
          },
          "Samples per cell width.")
      .def_property(
          "spp", [](const SceneState& s) { return s.integrator.spp; },
          [](SceneState& s, int v) {
            if (v < 1 || v > 4096) throw vs::UsageError("spp must be in [1, 4096]");
            s.integrator.spp = uint32_t(v);
          },
          "Rays per pixel.")
      .def_property(
          "shade", [](const SceneState& s) { return s.integrator.shade != 0; },
          [](SceneState& s, bool v) { s.integrator.shade = v ? 1 : 0; }, "Gradient (headlight) shading.")
      .def_property(
          "background", [](const SceneState& s) { return to_tuple(s.background); },
          [](SceneState& s, const Vec3Tuple& v) {
            for (double c : v)
              if (!(c >= 0 && c <= 1)) throw vs::UsageError("background expects R, G, B in [0, 1]");
            s.background = to_vec(v);
          },
          "sRGB background of save() and _repr_png_ (the array from render() has none).")
      .def(
          "render", [](SceneState& s) { return image_array(s.render()); },
          "Render the frame: an (H, W, 4) float32 array of premultiplied linear RGBA, rows top to bottom,\n"
          "owned by the module (no copy). Releases the GIL.")
      .def("save", &save, py::arg("path"), py::arg("background") = py::none(), py::arg("alpha") = false,
           "Render and write a .png (8-bit sRGB) or .pfm (float) file, over `background` (default: the\n"
           "scene's) unless alpha=True.")
      .def("_repr_png_", &repr_png, "The rendered frame as PNG bytes (Jupyter).")
      .def("__repr__", [](const SceneState& s) {
        return "<volstream.Scene field '" + s.ds->manifest().fields[size_t(s.field)].name + "' step " +
               std::to_string(s.step) + ", " + std::to_string(s.width) + "x" + std::to_string(s.height) + ">";
      });

  m.def("create_scene", &create_scene, py::arg("ds"), py::arg("field") = py::none(), py::arg("log") = false,
        py::arg("device") = "cpu",
        "A scene of `ds`: the field (default: the dataset's look, e.g. vorticity for the jet demo), a log\n"
        "scale, and the device (cpu | cuda | auto). Defaults match `volstream render DATASET`.");
}
