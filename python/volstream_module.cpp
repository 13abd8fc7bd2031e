// The Python module `volstream`: the library's frame recipe (frame/frame_renderer.h) for
// notebooks and scripts, with names close to yt's. It binds the library, not the command line:
// the defaults (field, transfer function, camera) come from frame/look.h, so
// `volstream.create_scene(ds).render()` is the image `volstream render DATASET` writes.
//   ds = volstream.load(path) or volstream.demo("jet")      a dataset (docs/python.md)
//   ds.probe(field, points)                                  values at world points
//   sc = volstream.create_scene(ds); sc.render()             (H, W, 4) premultiplied linear RGBA
// Errors: InputError -> OSError("<file>: <what>"), UsageError -> ValueError(<what>), the lines
// the command line prints. Rendering and probing release the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
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

DatasetPtr load(const std::string& path) {
  auto h = std::make_shared<DatasetHandle>();
  py::gil_scoped_release release;
  h->dataset = std::make_unique<vs::Dataset>(path);
  return h;
}

DatasetPtr demo(const std::string& name, double cells, int steps) {
  if (!(cells >= 1e4 && cells <= 2e9)) throw vs::UsageError("demo cells must be in [1e4, 2e9]");
  if (steps < 1 || steps > 1000) throw vs::UsageError("demo steps must be in [1, 1000]");
  auto h = std::make_shared<DatasetHandle>();
  py::gil_scoped_release release;
  h->temp_root = make_temp_dir("volstream_python_" + name + "_");  // removed with h, also on errors
  const std::filesystem::path dir = h->temp_root / "dataset";
  auto source = vs::make_demo({name, uint64_t(cells), steps});
  vs::convert_to_dataset(*source, dir, vs::ConvertOptions::silent());
  h->dataset = std::make_unique<vs::Dataset>(dir);
  return h;
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
  vs::IntegratorKind kind = vs::IntegratorKind::abr;
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
    r.kind = kind;
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
      "volstream: volume rendering of AMR data (ABRs, empty-space skipping, isosurfaces).\n\n"
      "    ds = volstream.load('dataset_dir')   # or volstream.demo('jet')\n"
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
                                        "An open native dataset directory (volstream.load or volstream.demo).")
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
          "World box of the leaf cells: ((x0, y0, z0), (x1, y1, z1)).")
      .def_property_readonly(
          "domain_left_edge", [](const DatasetHandle& h) { return to_tuple(h.domain().lower); },
          "Lower world corner of the leaf cells.")
      .def_property_readonly(
          "domain_right_edge", [](const DatasetHandle& h) { return to_tuple(h.domain().upper); },
          "Upper world corner of the leaf cells.")
      .def_property_readonly(
          "domain_center", [](const DatasetHandle& h) { return to_tuple(h.domain().center()); },
          "Centre of the world box.")
      .def_property_readonly(
          "cell_count", [](const DatasetHandle& h) { return h.manifest().cell_count; }, "Number of leaf cells.")
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
           "Through the ABRs (float32, as `volstream probe`), or with brute_force=True the tent-basis sum\n"
           "over every cell (float64, the reference). device: cpu | cuda | auto.")
      .def("__repr__", [](const DatasetHandle& h) {
        return "<volstream.Dataset '" + h.name() + "': " + std::to_string(h.manifest().cell_count) + " cells, " +
               std::to_string(h.manifest().fields.size()) + " fields, " + std::to_string(h.manifest().step_count()) +
               " steps>";
      });

  m.def("load", &load, py::arg("path"),
        "Open a native dataset directory (written by `volstream convert` or `volstream demo`).\n"
        "OSError('<file>: <what>') when it is missing or damaged.");
  m.def("demo", &demo, py::arg("name"), py::arg("cells") = 1e5, py::arg("steps") = 2,
        "A built-in demo ('jet' or 'cosmo') of about `cells` leaf cells and `steps` time steps, written to\n"
        "a private temporary directory that is removed when the Dataset is garbage-collected.");

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
          "distance; linear in between, constant outside. [] restores the default.");

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
          [](const SceneState& s) { return std::string(s.kind == vs::IntegratorKind::abr ? "abr" : "blocks"); },
          [](SceneState& s, const std::string& name) {
            if (name == "abr")
              s.kind = vs::IntegratorKind::abr;
            else if (name == "blocks")
              s.kind = vs::IntegratorKind::blocks;
            else
              throw vs::UsageError("integrator must be 'abr' or 'blocks', not '" + name + "'");
          },
          "abr: ABRs with empty-space skipping; blocks: the kd-tree block raycaster (trilinear).")
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
