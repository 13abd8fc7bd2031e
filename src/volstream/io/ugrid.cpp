#include "volstream/io/ugrid.h"

#include <array>
#include <charconv>
#include <span>
#include <vector>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/parse_cursor.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

struct UgridLayout {
  bool binary = false;
  bool big_endian = false;
  int real_bytes = 8;  // ints are always 4 bytes
};

UgridLayout layout_of(UgridEncoding e) {
  switch (e) {
    case UgridEncoding::ascii:
      return {false, false, 8};
    case UgridEncoding::b8:
      return {true, true, 8};
    case UgridEncoding::lb8:
      return {true, false, 8};
    case UgridEncoding::lb4:
      return {true, false, 4};
    case UgridEncoding::b4:
      return {true, true, 4};
  }
  return {};
}

UgridLayout layout_from_name(const fs::path& file) {
  if (file.extension() != ".ugrid") input_error(file.string(), "not a UGRID file name (expected *.ugrid)");
  const std::string infix = file.stem().extension().string();
  static const std::pair<const char*, UgridEncoding> kBinary[] = {{".b8", UgridEncoding::b8},
                                                                  {".lb8", UgridEncoding::lb8},
                                                                  {".lb4", UgridEncoding::lb4},
                                                                  {".b4", UgridEncoding::b4}};
  for (const auto& [name, encoding] : kBinary)
    if (infix == name) return layout_of(encoding);
  for (const char* unsupported : {".r8", ".r4", ".lr8", ".lr4", ".b8l", ".lb8l", ".r8l", ".lr8l"})
    if (infix == unsupported)
      input_error(file.string(), "UGRID variant '" + infix + "' is not supported (ascii, b8, lb8, b4, lb4 are)");
  return layout_of(UgridEncoding::ascii);  // any other infix is part of the case name
}

// The volume element kinds in file order, with the UGRID -> VTK vertex permutation
// (vtk[i] = ugrid[from_ugrid[i]], 0-based; see ugrid.h for the source).
struct VolumeKind {
  const char* name;
  CellType vtk_type;
  int vertices;
  std::array<int, 8> from_ugrid;
};
constexpr VolumeKind kVolumeKinds[] = {
    {"tet", CellType::tet, 4, {0, 1, 2, 3}},
    {"pyramid", CellType::pyramid, 5, {1, 0, 3, 4, 2}},
    {"prism", CellType::wedge, 6, {0, 1, 2, 3, 4, 5}},
    {"hex", CellType::hex, 8, {0, 1, 2, 3, 4, 5, 6, 7}},
};

struct UgridCounts {
  uint64_t nodes, surface_trias, surface_quads;
  std::array<uint64_t, 4> volumes;                                                 // in kVolumeKinds order
  uint64_t surface_ints() const { return 4 * surface_trias + 5 * surface_quads; }  // with surface ids
  uint64_t volume_ints() const {
    uint64_t n = 0;
    for (size_t k = 0; k < volumes.size(); ++k) n += volumes[k] * uint64_t(kVolumeKinds[k].vertices);
    return n;
  }
};

class UgridReader {
 public:
  explicit UgridReader(const fs::path& file) : layout_(layout_from_name(file)), in_(file) {}
  MeshData read();

 private:
  int64_t next_int(const char* what);
  double next_real(const char* what);
  UgridCounts read_counts();
  void check_size(const UgridCounts& c);
  void read_points(uint64_t nodes);
  void read_volume(const VolumeKind& kind, uint64_t count);

  UgridLayout layout_;
  ParseCursor in_;
  MeshData mesh_;
};

int64_t UgridReader::next_int(const char* what) {
  return layout_.binary ? in_.binary<int32_t>(layout_.big_endian, what) : in_.integer(what);
}

double UgridReader::next_real(const char* what) {
  if (!layout_.binary) return in_.real(what);
  return layout_.real_bytes == 4 ? in_.binary<float>(layout_.big_endian, what)
                                 : in_.binary<double>(layout_.big_endian, what);
}

UgridCounts UgridReader::read_counts() {
  static const char* kNames[] = {"node count",    "surface tria count", "surface quad count", "tet count",
                                 "pyramid count", "prism count",        "hex count"};
  std::array<uint64_t, 7> n{};
  for (int i = 0; i < 7; ++i) {
    const int64_t v = next_int(kNames[i]);
    if (v < 0 || v > INT32_MAX) in_.fail(std::string("bad ") + kNames[i] + " " + std::to_string(v));
    n[size_t(i)] = uint64_t(v);
  }
  return {n[0], n[1], n[2], {n[3], n[4], n[5], n[6]}};
}

// Counts below 2^31 keep these products far from overflow. Binary files must hold every byte the
// counts promise (more is fine: optional records follow); ascii files at least a byte per number.
void UgridReader::check_size(const UgridCounts& c) {
  const uint64_t ints = c.surface_ints() + c.volume_ints();
  if (!layout_.binary) return in_.require_fits(3 * c.nodes + ints, 1, "UGRID counts");
  const uint64_t needed = 3 * c.nodes * uint64_t(layout_.real_bytes) + 4 * ints;
  if (needed > in_.remaining())
    in_.fail("truncated: the counts need " + std::to_string(needed + 28) + " bytes, the file has " +
             std::to_string(in_.remaining() + 28));
}

void UgridReader::read_points(uint64_t nodes) {
  mesh_.points.resize(nodes);
  for (vec3d& p : mesh_.points) {
    p.x = next_real("x coordinate");
    p.y = next_real("y coordinate");
    p.z = next_real("z coordinate");
  }
}

void UgridReader::read_volume(const VolumeKind& kind, uint64_t count) {
  const uint64_t nodes = mesh_.points.size();
  std::array<uint64_t, 8> ugrid{};
  for (uint64_t e = 0; e < count; ++e) {
    for (int v = 0; v < kind.vertices; ++v) {
      const int64_t index = next_int("element node index");
      if (index < 1 || uint64_t(index) > nodes)
        in_.fail(std::string(kind.name) + " " + std::to_string(e + 1) + ": node index " + std::to_string(index) +
                 " out of range 1.." + std::to_string(nodes));
      ugrid[size_t(v)] = uint64_t(index - 1);
    }
    for (int v = 0; v < kind.vertices; ++v) mesh_.connectivity.push_back(ugrid[size_t(kind.from_ugrid[size_t(v)])]);
    mesh_.cell_types.push_back(uint8_t(kind.vtk_type));
    mesh_.cell_offsets.push_back(mesh_.connectivity.size());
  }
}

MeshData UgridReader::read() {
  const UgridCounts counts = read_counts();
  check_size(counts);
  read_points(counts.nodes);
  for (uint64_t i = 0; i < counts.surface_ints(); ++i) next_int("surface face data");  // bounds only
  uint64_t cells = 0;
  for (uint64_t n : counts.volumes) cells += n;
  mesh_.cell_types.reserve(cells);
  mesh_.cell_offsets.reserve(cells + 1);
  mesh_.connectivity.reserve(counts.volume_ints());
  mesh_.cell_offsets.push_back(0);
  for (size_t k = 0; k < counts.volumes.size(); ++k) read_volume(kVolumeKinds[k], counts.volumes[k]);
  check_mesh(mesh_, in_.file());
  return std::move(mesh_);
}

// ---------------------------------------------------------------------------------------------
// Writer.

class UgridWriter {
 public:
  explicit UgridWriter(UgridEncoding e) : layout_(layout_of(e)) {}
  std::string write(const MeshData& mesh);

 private:
  void ints(std::span<const int64_t> values);
  void reals(std::span<const double> values);

  UgridLayout layout_;
  std::string out_;
};

void UgridWriter::ints(std::span<const int64_t> values) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (layout_.binary) {
      append_value(out_, int32_t(values[i]), layout_.big_endian);
    } else {
      out_ += std::to_string(values[i]);
      out_ += i + 1 == values.size() ? '\n' : ' ';
    }
  }
}

void UgridWriter::reals(std::span<const double> values) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (layout_.binary) {
      layout_.real_bytes == 4 ? append_value(out_, float(values[i]), layout_.big_endian)
                              : append_value(out_, values[i], layout_.big_endian);
    } else {
      char buf[32];
      out_.append(buf, std::to_chars(buf, buf + sizeof buf, values[i]).ptr);  // shortest exact form
      out_ += i + 1 == values.size() ? '\n' : ' ';
    }
  }
}

std::string UgridWriter::write(const MeshData& mesh) {
  if (mesh.points.size() > uint64_t(INT32_MAX)) throw UsageError("too many points for a UGRID file");
  std::array<std::vector<uint64_t>, 4> cells_of_kind;  // cell ids per kVolumeKinds entry
  for (uint64_t c = 0; c < mesh.cell_count(); ++c) {
    size_t k = 0;
    while (k < 4 && uint8_t(kVolumeKinds[k].vtk_type) != mesh.cell_types[c]) ++k;
    if (k == 4) throw UsageError("UGRID cannot store cell type " + std::to_string(mesh.cell_types[c]));
    cells_of_kind[k].push_back(c);
  }
  ints(std::array<int64_t, 7>{int64_t(mesh.points.size()), 0, 0, int64_t(cells_of_kind[0].size()),
                              int64_t(cells_of_kind[1].size()), int64_t(cells_of_kind[2].size()),
                              int64_t(cells_of_kind[3].size())});
  for (const vec3d& p : mesh.points) reals(std::array<double, 3>{p.x, p.y, p.z});
  for (size_t k = 0; k < 4; ++k) {
    const VolumeKind& kind = kVolumeKinds[k];
    for (uint64_t c : cells_of_kind[k]) {
      std::array<int64_t, 8> ugrid{};
      for (int v = 0; v < kind.vertices; ++v)
        ugrid[size_t(kind.from_ugrid[size_t(v)])] = int64_t(mesh.connectivity[mesh.cell_offsets[c] + uint64_t(v)]) + 1;
      ints(std::span<const int64_t>(ugrid.data(), size_t(kind.vertices)));
    }
  }
  return std::move(out_);
}

}  // namespace

MeshData read_ugrid(const fs::path& file) { return UgridReader(file).read(); }

void write_ugrid(const fs::path& file, const MeshData& mesh, UgridEncoding encoding) {
  const std::string bytes = UgridWriter(encoding).write(mesh);
  write_file(file, bytes.data(), bytes.size());
}

MeshArray read_raw_scalars(uint64_t points, const std::string& name, const fs::path& raw_f32) {
  const uint64_t size = file_size_checked(raw_f32);
  const uint64_t expected = points * 4;
  if (size != expected)
    input_error(raw_f32.string(), "size " + std::to_string(size) + " bytes, expected " + std::to_string(expected) +
                                      " (one float32 per point, " + std::to_string(points) + " points)");
  std::string bytes(size, '\0');
  read_exact(raw_f32, 0, bytes.data(), size);
  MeshArray a;
  a.name = name;
  a.values.resize(points);
  for (size_t i = 0; i < a.values.size(); ++i) a.values[i] = load_value<float>(bytes.data() + 4 * i, false);
  return a;
}

void attach_raw_scalars(MeshData& mesh, const std::string& name, const fs::path& raw_f32) {
  mesh.point_data.push_back(read_raw_scalars(mesh.points.size(), name, raw_f32));
}

}  // namespace vs
