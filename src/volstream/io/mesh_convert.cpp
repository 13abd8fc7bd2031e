#include "volstream/io/mesh_convert.h"

#include <algorithm>

#include "volstream/core/error.h"
#include "volstream/core/progress.h"
#include "volstream/core/stopwatch.h"
#include "volstream/io/atomic_file.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs {
namespace fs = std::filesystem;

namespace {

class DemoSeries : public MeshSeries {
 public:
  explicit DemoSeries(MeshDemoOptions o) : options_(std::move(o)) { check_mesh_demo(options_); }
  int step_count() const override { return options_.steps; }
  MeshData read_step(int step) override { return make_mesh_demo(options_, step); }
  std::string origin(int) const override { return description(); }
  std::string description() const override { return "demo " + options_.name; }

 private:
  MeshDemoOptions options_;
};

std::vector<MeshFieldRef> selected(const std::vector<MeshFieldRef>& all, const std::vector<std::string>& wanted,
                                   const std::string& origin) {
  if (wanted.empty()) return all;
  std::vector<MeshFieldRef> out;
  for (const std::string& w : wanted) {
    const auto it = std::find_if(all.begin(), all.end(), [&](const MeshFieldRef& f) { return f.name == w; });
    if (it == all.end()) input_error(origin, "no field '" + w + "' (--fields)");
    out.push_back(*it);
  }
  return out;
}

}  // namespace

std::unique_ptr<MeshSeries> make_mesh_demo_series(const MeshDemoOptions& options) {
  return std::make_unique<DemoSeries>(options);
}

MeshConvertStats convert_mesh_to_dataset(MeshSeries& series, const fs::path& target_dir,
                                         const ConvertOptions& options) {
  MeshConvertStats stats;
  Stopwatch watch;
  if (options.file_order) throw UsageError("--file-order applies to AMR datasets, not meshes");
  MeshData first = series.read_step(0);
  stats.read_seconds += watch.lap();
  const std::string origin = series.origin(0);
  const WorldTransform transform = mesh_transform(first);
  if (const std::string problem = transform_problem(transform); !problem.empty()) input_error(origin, problem);
  const UMesh mesh = make_umesh(first, transform, origin);
  stats.encode_seconds = watch.lap();
  stats.elements = mesh.elements.size();
  stats.vertices = mesh.vertices.size();
  const std::vector<MeshFieldRef> fields = selected(mesh_fields(first), options.fields, origin);
  if (fields.empty()) input_error(origin, "the mesh has no point or cell data arrays to render");
  check_free_space(target_dir, 0, 0, false);

  StagedDirectory staged(target_dir, dataset_files::kManifest);
  DatasetManifest manifest;
  manifest.source = series.description();
  manifest.transform = transform;
  for (int s = 0; s < series.step_count(); ++s) manifest.step_times.push_back(series.step_time(s));
  std::vector<std::string> names;
  for (const MeshFieldRef& f : fields) names.push_back(f.name);
  DatasetWriter writer(staged.path(), manifest, names);
  writer.write_mesh(mesh);

  Progress progress("converting", uint64_t(series.step_count()) * fields.size(), !options.quiet);
  for (int step = 0; step < series.step_count(); ++step) {
    if (step > 0) {
      watch.lap();
      MeshData data = series.read_step(step);
      check_same_mesh(first, data, series.origin(step));
      first.point_data = std::move(data.point_data);
      first.cell_data = std::move(data.cell_data);
      stats.read_seconds += watch.lap();
    }
    // A later step must name the same arrays (with the same components) as the first.
    const std::vector<MeshFieldRef> here = mesh_fields(first);
    for (size_t f = 0; f < fields.size(); ++f) {
      progress.set_detail(fields[f].name + " step " + std::to_string(step));
      const auto it = std::find_if(here.begin(), here.end(), [&](const MeshFieldRef& r) {
        return r.name == fields[f].name && r.cell == fields[f].cell && r.component == fields[f].component;
      });
      if (it == here.end()) input_error(series.origin(step), "no field '" + fields[f].name + "' in this step");
      watch.lap();
      const std::vector<float> values = mesh_field_values(first, *it);
      check_field_values(values, series.origin(step), fields[f].name, step);
      writer.write_values(int(f), step, values);
      stats.values_seconds += watch.lap();
      progress.advance();
    }
  }
  progress.finish();
  writer.finish();
  staged.commit();
  return stats;
}

}  // namespace vs
