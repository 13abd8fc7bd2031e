#include "volstream/io/mesh_convert.h"

#include <algorithm>
#include <optional>
#include <regex>
#include <type_traits>

#include "volstream/amr/ranges.h"
#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/core/progress.h"
#include "volstream/core/release.h"
#include "volstream/core/stopwatch.h"
#include "volstream/io/atomic_file.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/cgns.h"
#include "volstream/io/ensight.h"
#include "volstream/io/exodus.h"
#include "volstream/io/fluent.h"
#include "volstream/io/gmsh.h"
#include "volstream/io/openfoam.h"
#include "volstream/io/ugrid.h"
#include "volstream/io/vtk_legacy.h"
#include "volstream/io/vtu.h"
#include "volstream/umesh/compact.h"
#include "volstream/umesh/from_mesh_data.h"
#include "volstream/umesh/mesh_pieces.h"
#include "volstream/umesh/spatial_order.h"
#include "volstream/umesh/split_tets.h"

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

// A Gmsh file as one step of several files (a .pvd's, or files given as a series), its physical
// groups `groups` (all when it is empty): one holding time steps of its own is converted on its own.
MeshData read_gmsh_step(const fs::path& file, const std::vector<std::string>& groups) {
  const GmshFile msh(file, groups);
  if (msh.step_count() > 1)
    input_error(file.string(), "holds " + std::to_string(msh.step_count()) +
                                   " time steps: give it on its own, not as one step of several files");
  return msh.read_step(0);
}

// A step's file; a .vtu or .vtm split with `splits` (a series', for its next step); of a .vtm
// the blocks, of a .msh the physical groups named in `regions` (all when it is empty).
MeshData read_mesh_file(const fs::path& file, SeriesSplits* splits = nullptr,
                        const std::vector<std::string>& regions = {}) {
  const std::string ext = lower_extension(file);
  if (ext == ".vtu") return read_vtu(file, splits);
  if (ext == ".pvtu") return read_pvtu(file);
  if (ext == ".vtm") return read_vtm(file, splits, regions);
  if (ext == ".vtk") return read_vtk_legacy(file);
  if (ext == ".ugrid") return read_ugrid(file);
  if (ext == ".msh") return read_gmsh_step(file, regions);
  input_error(file.string(),
              "not a mesh file (.vtu, .pvtu, .vtm, .vtk, .ugrid, .msh, or a .pvd or .series of them; or an EnSight "
              ".case or an Exodus II .exo, or a .cgns, or a Fluent .cas and its .dat files, or an OpenFOAM case)");
}

// A step's parts (a .pvd's entries of one time: a parallel run's pieces) as one mesh, read in
// parallel; the error is the first bad part's.
MeshData read_parts(const std::vector<fs::path>& parts, const std::string& origin, SeriesSplits* splits,
                    const std::vector<std::string>& regions) {
  if (parts.size() == 1) return read_mesh_file(parts.front(), splits, regions);
  std::vector<MeshData> meshes(parts.size());
  parallel_each_in_order(int64_t(parts.size()),
                         [&](int64_t i) { meshes[size_t(i)] = read_mesh_file(parts[size_t(i)], nullptr, regions); });
  MeshData m = join_pieces(std::move(meshes), origin);
  check_mesh(m, origin);
  return m;
}

class FileSeries : public MeshSeries {
 public:
  // regions: the .vtm blocks or Gmsh physical groups to read (--region; empty: all).
  FileSeries(std::vector<PvdStep> steps, std::vector<RawScalars> scalars, std::string description,
             std::vector<std::string> regions)
      : steps_(std::move(steps)),
        scalars_(std::move(scalars)),
        description_(std::move(description)),
        regions_(std::move(regions)) {}
  int step_count() const override { return int(steps_.size()); }
  double step_time(int step) const override { return steps_.at(size_t(step)).time; }
  MeshData read_step(int step) override {
    MeshData m =
        read_parts(steps_.at(size_t(step)).parts, origin(step), steps_.size() > 1 ? &splits_ : nullptr, regions_);
    for (const RawScalars& s : scalars_) attach_raw_scalars(m, s.name, s.file);
    return m;
  }
  std::string origin(int step) const override { return steps_.at(size_t(step)).parts.front().string(); }
  std::string description() const override { return description_; }

 private:
  std::vector<PvdStep> steps_;
  std::vector<RawScalars> scalars_;
  std::string description_;
  std::vector<std::string> regions_;
  SeriesSplits splits_;  // the last step's, for the next
};

// An EnSight Gold case: its geometry is read once unless it changes from step to step.
class EnsightSeries : public MeshSeries {
 public:
  EnsightSeries(const fs::path& file, std::vector<RawScalars> scalars, std::vector<std::string> parts)
      : file_(file), case_(read_ensight_case(file)), scalars_(std::move(scalars)), parts_(std::move(parts)) {}
  int step_count() const override { return int(case_.times.size()); }
  double step_time(int step) const override { return case_.times.at(size_t(step)); }
  MeshData read_step(int step) override {
    if (case_.geometry_changes() || !geometry_) geometry_ = read_ensight_geometry(origin(step), parts_);
    MeshData m = read_ensight_step(case_, *geometry_, size_t(step));
    for (const RawScalars& s : scalars_) attach_raw_scalars(m, s.name, s.file);
    return m;
  }
  std::string origin(int step) const override {
    return ensight_step_file(case_, case_.geometry, size_t(step)).string();
  }
  std::string description() const override {
    const size_t steps = case_.times.size();
    std::vector<std::string> notes;
    if (steps > 1) notes.push_back(std::to_string(steps) + " steps");
    if (!parts_.empty()) notes.push_back("parts " + joined(parts_));
    return "EnSight Gold case " + file_.filename().string() + (notes.empty() ? "" : " (" + joined(notes, "; ") + ")");
  }

 private:
  fs::path file_;
  EnsightCase case_;
  std::vector<RawScalars> scalars_;
  std::vector<std::string> parts_;  // to read (empty: all)
  std::optional<EnsightGeometry> geometry_;
};

bool has_exodus_extension(const std::string& name) {
  static const char* const kExtensions[] = {".exo", ".e", ".ex2", ".exii", ".g", ".gen"};
  const std::string lower = lower_case(name);
  return std::any_of(std::begin(kExtensions), std::end(kExtensions), [&](const char* e) { return lower.ends_with(e); });
}

// Exodus files written one per rank, NAME.N.R for rank R (0 .. N-1, zero-padded to N's digits)
// of N: what Sierra, MOOSE's Nemesis output and SEACAS's decomp leave, before epu joins them.
struct ExodusRankFile {
  std::string base;  // NAME, an Exodus file name
  int ranks = 0, rank = 0;
};
std::optional<ExodusRankFile> exodus_rank_file(const fs::path& file) {
  static const std::regex kPattern(R"((.+)\.([0-9]{1,6})\.([0-9]{1,6}))");
  std::smatch m;
  const std::string name = file.filename().string();
  if (!std::regex_match(name, m, kPattern) || !has_exodus_extension(m[1].str())) return std::nullopt;
  const int ranks = std::stoi(m[2].str()), rank = std::stoi(m[3].str());
  if (ranks < 1 || rank >= ranks || m[3].str().size() != m[2].str().size()) return std::nullopt;
  return ExodusRankFile{m[1].str(), ranks, rank};
}

bool is_exodus_file(const fs::path& file) {
  return has_exodus_extension(file.filename().string()) || exodus_rank_file(file).has_value();
}

// Every rank file of the set `file` belongs to, in rank order (UsageError naming a missing one).
std::vector<fs::path> exodus_rank_files(const fs::path& file) {
  const ExodusRankFile set = *exodus_rank_file(file);
  const int width = int(std::to_string(set.ranks).size());
  std::vector<fs::path> files;
  for (int r = 0; r < set.ranks; ++r) {
    std::string rank = std::to_string(r);
    rank.insert(0, size_t(width) - rank.size(), '0');
    files.push_back(file.parent_path() / (set.base + "." + std::to_string(set.ranks) + "." + rank));
    if (!fs::exists(files.back()))
      throw UsageError("rank file " + files.back().string() + " of " + std::to_string(set.ranks) + " is missing");
  }
  return files;
}

// A summary and, for more than one, the step count after it ("...; 8 steps").
std::string with_step_count(const std::string& summary, size_t steps) {
  return steps > 1 ? summary + "; " + std::to_string(steps) + " steps" : summary;
}

// A solver's file holding its time steps (an Exodus II, CGNS or Gmsh file), or the rank files of one
// (Exodus): the mesh read once, each step's values from the same files; rank files' meshes joined
// (umesh/mesh_pieces.h: the nodes they share welded).
template <class File>
class SolverFileSeries : public MeshSeries {
 public:
  // `parts`: the parts of the model to read (an Exodus file's element blocks, a CGNS file's
  // zones, a Gmsh file's physical groups), for a File that takes them; empty: all.
  SolverFileSeries(const std::vector<fs::path>& files, std::vector<RawScalars> scalars, std::string format,
                   const std::vector<std::string>& parts = {})
      : files_(files), scalars_(std::move(scalars)), format_(std::move(format)) {
    for (const fs::path& f : files_) {
      if constexpr (std::is_constructible_v<File, const fs::path&, const std::vector<std::string>&>)
        pieces_.push_back(std::make_unique<File>(f, parts));
      else
        pieces_.push_back(std::make_unique<File>(f));
      if (pieces_.size() > 1 && !same_times(*pieces_.front(), *pieces_.back()))
        input_error(f.string(), "other time steps than " + files_.front().filename().string() + "'s");
    }
  }
  int step_count() const override { return int(pieces_.front()->step_count()); }
  double step_time(int step) const override { return pieces_.front()->step_time(size_t(step)); }
  MeshData read_step(int step) override {
    std::vector<MeshData> meshes;
    for (auto& p : pieces_) meshes.push_back(p->read_step(size_t(step)));  // one at a time: NetCDF is not thread-safe
    MeshData m = meshes.size() == 1 ? std::move(meshes.front()) : join_pieces(std::move(meshes), origin(step));
    input_check(m.cell_count() > 0, origin(step), "no volume elements in the parts asked for (--region)");
    if (pieces_.size() > 1) check_mesh(m, origin(step));
    for (const RawScalars& s : scalars_) attach_raw_scalars(m, s.name, s.file);
    return m;
  }
  std::string origin(int) const override { return files_.front().string(); }
  std::string description() const override {
    const size_t steps = pieces_.front()->step_count();
    const std::string what = pieces_.size() == 1
                                 ? pieces_.front()->summary()
                                 : std::to_string(pieces_.size()) + " rank files, " +
                                       pieces_.front()->summary().substr(0, pieces_.front()->summary().find(':'));
    return format_ + " " + files_.front().filename().string() + " (" + with_step_count(what, steps) + ")";
  }

 private:
  static bool same_times(const File& a, const File& b) {
    if (a.step_count() != b.step_count()) return false;
    for (size_t s = 0; s < a.step_count(); ++s)
      if (a.step_time(s) != b.step_time(s)) return false;
    return true;
  }
  std::vector<fs::path> files_;
  std::vector<std::unique_ptr<File>> pieces_;
  std::vector<RawScalars> scalars_;
  std::string format_;
};

// A solver's case whose mesh is read once and whose steps' values come from files of their own
// (a Fluent case and its data files, io/fluent.h; an OpenFOAM case's time directories,
// io/openfoam.h): `title` names it in the description.
template <class Case>
class CaseSeries : public MeshSeries {
 public:
  CaseSeries(std::unique_ptr<Case> c, std::string title, std::vector<RawScalars> scalars)
      : case_(std::move(c)), title_(std::move(title)), scalars_(std::move(scalars)) {}
  int step_count() const override { return int(case_->step_count()); }
  double step_time(int step) const override { return case_->step_time(size_t(step)); }
  MeshData read_step(int step) override { return with_scalars(case_->read_step(size_t(step))); }
  MeshData read_first_step() override { return with_scalars(case_->take_step(0)); }
  bool steps_need_points_alone() const override { return true; }
  StepData read_step_data(int step, const MeshData& first) override {
    StepData data{{}, case_->read_cell_data(size_t(step))};
    for (const RawScalars& s : scalars_)
      data.point_data.push_back(read_raw_scalars(first.points.size(), s.name, s.file));
    return data;
  }
  std::string origin(int step) const override { return case_->step_file(size_t(step)).string(); }
  std::string description() const override {
    return title_ + " (" + with_step_count(case_->summary(), case_->step_count()) + ")";
  }

 private:
  MeshData with_scalars(MeshData m) const {
    for (const RawScalars& s : scalars_) attach_raw_scalars(m, s.name, s.file);
    return m;
  }
  std::unique_ptr<Case> case_;
  std::string title_;
  std::vector<RawScalars> scalars_;
};

// A Fluent case file and the data files after it (UsageError for any other file among them).
std::unique_ptr<MeshSeries> open_fluent_files(const std::vector<fs::path>& files, std::vector<RawScalars> scalars,
                                              const std::vector<std::string>& zones) {
  const std::vector<fs::path> data(files.begin() + 1, files.end());
  for (const fs::path& f : data)
    if (!is_fluent_data_file(f))
      throw UsageError(f.string() +
                       " is not a Fluent data file (.dat, .dat.gz): a .cas is converted with its data files");
  return std::make_unique<CaseSeries<FluentFile>>(std::make_unique<FluentFile>(files.front(), data, zones),
                                                  "Fluent case " + files.front().filename().string(),
                                                  std::move(scalars));
}

// An OpenFOAM case, named by its directory (io/openfoam.h).
std::unique_ptr<MeshSeries> open_openfoam_case(const fs::path& input, std::vector<RawScalars> scalars,
                                               const std::vector<std::string>& regions) {
  auto c = std::make_unique<OpenFoamCase>(input, regions);
  const fs::path dir = fs::absolute(c->case_directory()).lexically_normal();
  const std::string name = (dir.has_filename() ? dir : dir.parent_path()).filename().string();
  return std::make_unique<CaseSeries<OpenFoamCase>>(std::move(c), "OpenFOAM case " + name, std::move(scalars));
}

bool is_cgns_file(const fs::path& file) {
  const std::string ext = lower_extension(file);
  return ext == ".cgns" || ext == ".cgn";
}

std::string format_name(const fs::path& file) {
  const std::string ext = lower_extension(file);
  if (ext == ".vtu") return "VTK XML unstructured grid";
  if (ext == ".pvtu") return "VTK XML parallel unstructured grid";
  if (ext == ".vtm") return "VTK XML multiblock";
  if (ext == ".vtk") return "legacy VTK unstructured grid";
  if (ext == ".pvd") return "ParaView collection";
  if (ext == ".series") return "ParaView file series";
  if (ext == ".msh") return "Gmsh";
  return "UGRID";
}

}  // namespace

std::string region_formats() {
  return "--region applies to OpenFOAM cases, Fluent case files, Exodus II, CGNS, EnSight, Gmsh and VTK multiblock "
         "(.vtm) files";
}

bool is_mesh_file(const fs::path& file) {
  const std::string ext = lower_extension(file);
  return ext == ".vtu" || ext == ".pvtu" || ext == ".vtm" || ext == ".vtk" || ext == ".pvd" || ext == ".series" ||
         ext == ".ugrid" || ext == ".case" || ext == ".msh" || is_exodus_file(file) || is_cgns_file(file) ||
         is_fluent_case_file(file) || is_openfoam_input(file);
}

RawScalars parse_raw_scalars(const std::string& spec) {
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
    throw UsageError("--scalars takes NAME=FILE (a raw float32 file, one value per point), not '" + spec + "'");
  return {spec.substr(0, eq), spec.substr(eq + 1)};
}

std::unique_ptr<MeshSeries> open_mesh_files(const std::vector<fs::path>& files, const std::vector<RawScalars>& scalars,
                                            const std::vector<std::string>& regions) {
  if (files.empty()) throw UsageError("no mesh files given");
  std::vector<PvdStep> steps;
  const std::string ext = lower_extension(files.front());
  if (!regions.empty() && !is_openfoam_input(files.front()) && !is_fluent_case_file(files.front()) &&
      !is_exodus_file(files.front()) && !is_cgns_file(files.front()) && ext != ".msh" && ext != ".case" &&
      ext != ".vtm" && ext != ".pvd" && ext != ".series")
    throw UsageError(region_formats() + " (" + files.front().string() + " is none of them)");
  if (ext == ".case") {
    if (files.size() > 1) throw UsageError("an EnSight .case file is converted on its own");
    return std::make_unique<EnsightSeries>(files.front(), scalars, regions);
  }
  if (exodus_rank_file(files.front())) {
    // One rank file names its set; several must be the whole set.
    const std::vector<fs::path> set = exodus_rank_files(files.front());
    if (files.size() > 1 && files.size() != set.size())
      throw UsageError("give one rank file of an Exodus set, or all " + std::to_string(set.size()) + " of them");
    for (const fs::path& f : files)
      if (std::find(set.begin(), set.end(), f) == set.end())
        throw UsageError(f.string() + " is not a rank file of " + files.front().string() + "'s set");
    return std::make_unique<SolverFileSeries<ExodusFile>>(set, scalars, "Exodus II", regions);
  }
  if (is_exodus_file(files.front())) {
    if (files.size() > 1) throw UsageError("an Exodus II file is converted on its own (it holds its time steps)");
    return std::make_unique<SolverFileSeries<ExodusFile>>(files, scalars, "Exodus II", regions);
  }
  if (is_cgns_file(files.front())) {
    if (files.size() > 1) throw UsageError("a CGNS file is converted on its own (it holds its time steps)");
    return std::make_unique<SolverFileSeries<CgnsFile>>(files, scalars, "CGNS", regions);
  }
  if (is_fluent_case_file(files.front())) return open_fluent_files(files, scalars, regions);
  if (is_openfoam_input(files.front())) {
    if (files.size() > 1)
      throw UsageError("an OpenFOAM case is converted on its own (its time directories are its steps)");
    return open_openfoam_case(files.front(), scalars, regions);
  }
  if (ext == ".msh" && files.size() == 1)
    return std::make_unique<SolverFileSeries<GmshFile>>(files, scalars, "Gmsh", regions);
  if (ext == ".pvd" || ext == ".series") {
    if (files.size() > 1) throw UsageError("a .pvd collection or .series file is converted on its own");
    steps = ext == ".pvd" ? read_pvd(files.front()) : read_file_series(files.front());
  } else {
    for (size_t i = 0; i < files.size(); ++i) steps.push_back({double(i), {files[i]}});
  }
  // --region on a series (files, a .pvd or a .series): every step a .vtm, or every step a .msh.
  const std::string step_ext = steps.empty() || steps[0].parts.empty() ? "" : lower_extension(steps[0].parts[0]);
  for (const PvdStep& step : steps)
    for (const fs::path& part : step.parts)
      if (!regions.empty() && (lower_extension(part) != step_ext || (step_ext != ".vtm" && step_ext != ".msh")))
        throw UsageError("--region applies to a series of .vtm files or of .msh files (" + part.string() +
                         " is not one of them)");
  std::string description = format_name(files.front()) + " " + files.front().filename().string();
  std::vector<std::string> notes;
  if (steps.size() > 1) notes.push_back(std::to_string(steps.size()) + " steps");
  if (!regions.empty()) notes.push_back((step_ext == ".vtm" ? "blocks " : "physical groups ") + joined(regions));
  if (!notes.empty()) description += " (" + joined(notes, "; ") + ")";
  return std::make_unique<FileSeries>(std::move(steps), scalars, description, regions);
}

StepData MeshSeries::read_step_data(int step, const MeshData& first) {
  MeshData m = read_step(step);
  check_same_mesh(first, m, origin(step));
  return {std::move(m.point_data), std::move(m.cell_data)};
}

std::unique_ptr<MeshSeries> make_mesh_demo_series(const MeshDemoOptions& options) {
  return std::make_unique<DemoSeries>(options);
}

MeshConvertStats convert_mesh_to_dataset(MeshSeries& series, const fs::path& target_dir,
                                         const ConvertOptions& options) {
  MeshConvertStats stats;
  Stopwatch watch;
  if (options.file_order) throw UsageError("--file-order applies to AMR datasets, not meshes");
  MeshData first = series.read_first_step();
  stats.read_seconds += watch.lap();
  const std::string origin = series.origin(0);
  const WorldTransform transform = mesh_transform(first);
  if (const std::string problem = transform_problem(transform); !problem.empty()) input_error(origin, problem);
  // Stored in spatial order (umesh/spatial_order.h): elements and vertices are renumbered, each
  // step's values with them; inputs are checked in the file's numbering, which messages name.
  MeshOrder order;
  DatasetManifest manifest;
  const UMesh mesh = [&] {
    UMesh as_read = make_umesh(first, transform, origin);
    if (options.split_into_tets) {
      for (int t = 0; t < 4; ++t) manifest.mesh.split_from[t] = as_read.count_by_type[t];
      as_read = split_into_tets(std::move(as_read));
    }
    order = spatial_order(as_read);
    return reordered(as_read, order);
  }();
  stats.encode_seconds = watch.lap();
  stats.elements = mesh.elements.size();
  stats.vertices = mesh.vertices.size();
  const std::vector<MeshFieldRef> fields = selected(mesh_fields(first), options.fields, origin);
  if (fields.empty()) input_error(origin, "the mesh has no point or cell data arrays to render");
  // The cells around each point, for cell arrays averaged to the points (the same every step).
  std::optional<PointCells> point_cells;
  if (std::any_of(fields.begin(), fields.end(), [](const MeshFieldRef& f) { return f.cell; }))
    point_cells = point_cells_of(first);
  if (series.steps_need_points_alone()) {  // the first step's cells are not needed any more
    release(first.cell_types);
    release(first.cell_offsets);
    release(first.connectivity);
  }
  check_free_space(target_dir, 0, 0, false);

  StagedDirectory staged(target_dir, dataset_files::kManifest);
  manifest.source = series.description();
  manifest.transform = transform;
  for (int s = 0; s < series.step_count(); ++s) manifest.step_times.push_back(series.step_time(s));
  std::vector<std::string> names;
  for (const MeshFieldRef& f : fields) names.push_back(f.name);
  DatasetWriter writer(staged.path(), manifest, names);
  // Compact: the values of each step are stored per local vertex, so a render reads a step
  // straight into what the sampler reads.
  const bool compact = options.mesh_encoding == MeshEncoding::compact;
  const CompactMesh compact_mesh = compact ? build_compact_mesh(mesh) : CompactMesh{};
  if (compact)
    writer.write_compact_mesh(mesh, compact_mesh);
  else
    writer.write_mesh(mesh);
  stats.encode_seconds += watch.lap();  // the point-location structures of either encoding

  Progress progress("converting", uint64_t(series.step_count()) * fields.size(), !options.quiet);
  for (int step = 0; step < series.step_count(); ++step) {
    if (step > 0) {
      watch.lap();
      // The last step's values go before this step's come: a solver case's cell arrays are the
      // largest thing a convert holds (read_step_data needs the mesh of `first` alone).
      release(first.point_data);
      release(first.cell_data);
      StepData data = series.read_step_data(step, first);
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
      const std::vector<float> file_values = mesh_field_values(first, *it, point_cells ? &*point_cells : nullptr);
      check_field_values(file_values, series.origin(step), fields[f].name, step);
      const std::vector<float> values = reordered_values(file_values, order);
      if (compact)  // the step's range over every vertex, as the reference encoding has it
        writer.write_values(int(f), step, compact_mesh.gather(values.data()),
                            value_range(values.data(), values.size()));
      else
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
