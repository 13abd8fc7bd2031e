#include "volstream/io/vtk_legacy.h"

#include <charconv>
#include <climits>
#include <vector>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/parse_cursor.h"
#include "volstream/umesh/polyhedra.h"
#include "volstream/umesh/quadratic.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Value types as legacy VTK names them.

enum class VtkType { i8, u8, i16, u16, i32, u32, i64, u64, f32, f64 };

struct VtkTypeName {
  const char* name;
  VtkType type;
};
constexpr VtkTypeName kTypeNames[] = {
    {"char", VtkType::i8},           {"signed_char", VtkType::i8},     {"unsigned_char", VtkType::u8},
    {"short", VtkType::i16},         {"unsigned_short", VtkType::u16}, {"int", VtkType::i32},
    {"unsigned_int", VtkType::u32},  {"long", VtkType::i64},           {"unsigned_long", VtkType::u64},
    {"vtkidtype", VtkType::i64},     {"vtktypeint8", VtkType::i8},     {"vtktypeuint8", VtkType::u8},
    {"vtktypeint16", VtkType::i16},  {"vtktypeuint16", VtkType::u16},  {"vtktypeint32", VtkType::i32},
    {"vtktypeuint32", VtkType::u32}, {"vtktypeint64", VtkType::i64},   {"vtktypeuint64", VtkType::u64},
    {"float", VtkType::f32},         {"double", VtkType::f64},
};

size_t type_size(VtkType t) {
  switch (t) {
    case VtkType::i8:
    case VtkType::u8:
      return 1;
    case VtkType::i16:
    case VtkType::u16:
      return 2;
    case VtkType::i32:
    case VtkType::u32:
    case VtkType::f32:
      return 4;
    default:
      return 8;
  }
}
bool is_integer_type(VtkType t) { return t != VtkType::f32 && t != VtkType::f64; }

// Binary values are big endian. Unsigned 64-bit values past INT64_MAX come back as negative
// int64, which every caller refuses as an index or count.
int64_t decode_integer(const char* p, VtkType t) {
  switch (t) {
    case VtkType::i8:
      return int8_t(*p);
    case VtkType::u8:
      return uint8_t(*p);
    case VtkType::i16:
      return load_value<int16_t>(p, true);
    case VtkType::u16:
      return load_value<uint16_t>(p, true);
    case VtkType::i32:
      return load_value<int32_t>(p, true);
    case VtkType::u32:
      return load_value<uint32_t>(p, true);
    default:
      return load_value<int64_t>(p, true);
  }
}
double decode_real(const char* p, VtkType t) {
  switch (t) {
    case VtkType::f32:
      return load_value<float>(p, true);
    case VtkType::f64:
      return load_value<double>(p, true);
    case VtkType::u64:
      return double(load_value<uint64_t>(p, true));
    default:
      return double(decode_integer(p, t));
  }
}

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

// ---------------------------------------------------------------------------------------------
// Reader. Every section starts with a keyword line; its arguments are on the same line, and in
// BINARY files the data starts right after that line's end.

class VtkReader {
 public:
  explicit VtkReader(const fs::path& path) : in_(path) {}
  MeshData read();

 private:
  void read_header();
  void read_section(const std::string& keyword);
  std::vector<std::string_view> arguments(const std::string& keyword, size_t min_count, size_t max_count);
  uint64_t count_argument(std::string_view word, const char* what);
  VtkType type_argument(std::string_view word);
  int component_count(std::string_view word);

  void read_points(const std::vector<std::string_view>& args);
  void read_cells(const std::vector<std::string_view>& args);
  void read_count_prefixed_cells(uint64_t cells, uint64_t size);
  void read_offset_cells(uint64_t offsets, uint64_t connectivity);
  void read_cell_types(const std::vector<std::string_view>& args);
  void start_attributes(const std::string& keyword, const std::vector<std::string_view>& args);
  void read_attribute(const std::string& keyword, const std::vector<std::string_view>& args);
  void read_scalars(const std::vector<std::string_view>& args);
  void read_field(const std::vector<std::string_view>& args);
  void read_field_array();
  void skip_lookup_table(const std::vector<std::string_view>& args);
  void skip_metadata();
  void add_array(std::string_view name, int components, VtkType type);
  void finish();

  std::vector<int64_t> read_integers(uint64_t count, VtkType type, const char* what);
  std::vector<double> read_reals(uint64_t count, VtkType type, const char* what);

  ParseCursor in_;
  bool binary_ = false;
  int major_version_ = 0;
  bool pre_vtk91_lagrange_ = false;  // version below 5.1: Lagrange hexahedra in the old node order
  MeshData mesh_;
  bool have_points_ = false, have_cells_ = false, have_types_ = false;
  std::vector<MeshArray>* attributes_ = nullptr;  // the POINT_DATA or CELL_DATA being read
  uint64_t attribute_tuples_ = 0;
};

MeshData VtkReader::read() {
  read_header();
  while (const auto word = in_.try_word()) read_section(lower_case(*word));
  finish();
  return std::move(mesh_);
}

void VtkReader::read_header() {
  const std::string_view magic = in_.line();
  constexpr std::string_view kMagic = "# vtk DataFile Version ";
  if (magic.substr(0, kMagic.size()) != kMagic) in_.fail("not a legacy VTK file (no '# vtk DataFile Version' line)");
  const std::string_view version = magic.substr(kMagic.size());
  const auto [end, ec] = std::from_chars(version.data(), version.data() + version.size(), major_version_);
  if (ec != std::errc() || major_version_ < 1) in_.fail("bad version '" + std::string(version) + "'");
  pre_vtk91_lagrange_ = version_below(version, 5, 1);
  in_.skip_line();  // title
  const std::string format = lower_case(in_.word("ASCII or BINARY"));
  if (format != "ascii" && format != "binary") in_.fail("expected ASCII or BINARY, found '" + format + "'");
  binary_ = format == "binary";
  in_.skip_line();
  if (lower_case(in_.word("DATASET")) != "dataset") in_.fail("expected DATASET");
  const auto args = arguments("DATASET", 1, 1);
  if (lower_case(args[0]) != "unstructured_grid")
    in_.fail("dataset type " + std::string(args[0]) + " is not supported (only UNSTRUCTURED_GRID)");
}

std::vector<std::string_view> VtkReader::arguments(const std::string& keyword, size_t min_count, size_t max_count) {
  std::vector<std::string_view> args = split_words(in_.line());
  if (args.size() < min_count || args.size() > max_count)
    in_.fail(keyword + ": expected " + std::to_string(min_count) +
             (max_count > min_count ? " to " + std::to_string(max_count) : "") + " values on its line, found " +
             std::to_string(args.size()));
  return args;
}

uint64_t VtkReader::count_argument(std::string_view word, const char* what) {
  uint64_t v = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
  if (ec != std::errc() || end != word.data() + word.size())
    in_.fail(std::string("bad ") + what + " '" + std::string(word.substr(0, 40)) + "'");
  return v;
}

// Components per tuple; a bound that keeps a damaged count from overflowing.
int VtkReader::component_count(std::string_view word) {
  const uint64_t n = count_argument(word, "component count");
  if (n < 1 || n > 256) in_.fail("bad component count " + std::to_string(n));
  return int(n);
}

VtkType VtkReader::type_argument(std::string_view word) {
  const std::string name = lower_case(word);
  for (const VtkTypeName& t : kTypeNames)
    if (name == t.name) return t.type;
  in_.fail("unsupported data type '" + std::string(word.substr(0, 40)) + "'");
}

void VtkReader::read_section(const std::string& keyword) {
  if (keyword == "metadata") return skip_metadata();
  if (keyword == "points") return read_points(arguments("POINTS", 2, 2));
  if (keyword == "cells") return read_cells(arguments("CELLS", 2, 2));
  if (keyword == "cell_types") return read_cell_types(arguments("CELL_TYPES", 1, 1));
  if (keyword == "point_data" || keyword == "cell_data") return start_attributes(keyword, arguments(keyword, 1, 1));
  if (keyword == "field") return read_field(arguments("FIELD", 2, 2));
  if (keyword == "lookup_table") return skip_lookup_table(arguments("LOOKUP_TABLE", 2, 2));
  if (keyword == "scalars" || keyword == "vectors" || keyword == "normals" || keyword == "tensors" ||
      keyword == "texture_coordinates" || keyword == "color_scalars")
    return read_attribute(keyword, arguments(keyword, 2, 4));
  in_.fail("unknown keyword '" + keyword.substr(0, 40) + "'");
}

std::vector<int64_t> VtkReader::read_integers(uint64_t count, VtkType type, const char* what) {
  if (!is_integer_type(type)) in_.fail(std::string(what) + ": expected an integer type");
  in_.require_fits(count, binary_ ? type_size(type) : 1, what);
  std::vector<int64_t> out(count);
  if (binary_) {
    const char* p = in_.take(count * type_size(type), what);
    for (uint64_t i = 0; i < count; ++i) out[i] = decode_integer(p + i * type_size(type), type);
  } else {
    for (int64_t& v : out) v = in_.integer(what);
  }
  return out;
}

std::vector<double> VtkReader::read_reals(uint64_t count, VtkType type, const char* what) {
  in_.require_fits(count, binary_ ? type_size(type) : 1, what);
  std::vector<double> out(count);
  if (binary_) {
    const char* p = in_.take(count * type_size(type), what);
    for (uint64_t i = 0; i < count; ++i) out[i] = decode_real(p + i * type_size(type), type);
  } else {
    // Values declared float are float in VTK too: "2.1" means float(2.1).
    for (double& v : out) v = type == VtkType::f32 ? double(float(in_.real(what))) : in_.real(what);
  }
  return out;
}

void VtkReader::read_points(const std::vector<std::string_view>& args) {
  if (have_points_) in_.fail("a second POINTS section");
  const uint64_t n = count_argument(args[0], "point count");
  in_.require_fits(n, 3 * (binary_ ? type_size(type_argument(args[1])) : 1), "POINTS");
  const std::vector<double> xyz = read_reals(3 * n, type_argument(args[1]), "point coordinates");
  mesh_.points.resize(n);
  for (uint64_t i = 0; i < n; ++i) mesh_.points[i] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  have_points_ = true;
}

void VtkReader::read_cells(const std::vector<std::string_view>& args) {
  if (have_cells_) in_.fail("a second CELLS section");
  const uint64_t first = count_argument(args[0], "cell count"), second = count_argument(args[1], "cell size");
  if (major_version_ >= 5)
    read_offset_cells(first, second);
  else
    read_count_prefixed_cells(first, second);
  have_cells_ = true;
}

// Version < 5: `size` ints holding, per cell, its vertex count and then its vertices.
void VtkReader::read_count_prefixed_cells(uint64_t cells, uint64_t size) {
  const std::vector<int64_t> lists = read_integers(size, VtkType::i32, "cell lists");
  if (cells > size)
    in_.fail("CELLS: " + std::to_string(cells) + " cells cannot fit in " + std::to_string(size) + " ints");
  mesh_.cell_offsets.reserve(cells + 1);
  mesh_.connectivity.reserve(size - cells);
  mesh_.cell_offsets.push_back(0);
  uint64_t pos = 0;
  for (uint64_t c = 0; c < cells; ++c) {
    if (pos >= size) in_.fail("CELLS: the cell lists end before cell " + std::to_string(c));
    const int64_t count = lists[pos++];
    if (count < 0 || uint64_t(count) > size - pos)
      in_.fail("CELLS: cell " + std::to_string(c) + " has a bad vertex count " + std::to_string(count));
    for (int64_t k = 0; k < count; ++k) {
      if (lists[pos] < 0) in_.fail("CELLS: negative point index in cell " + std::to_string(c));
      mesh_.connectivity.push_back(uint64_t(lists[pos++]));
    }
    mesh_.cell_offsets.push_back(mesh_.connectivity.size());
  }
  if (pos != size)
    in_.fail("CELLS: size " + std::to_string(size) + " but the cell lists use " + std::to_string(pos) + " ints");
}

// Version >= 5: OFFSETS (cells + 1 entries) and CONNECTIVITY arrays.
void VtkReader::read_offset_cells(uint64_t offsets, uint64_t connectivity) {
  if (lower_case(in_.word("OFFSETS")) != "offsets") in_.fail("CELLS: expected OFFSETS");
  const VtkType offset_type = type_argument(arguments("OFFSETS", 1, 1)[0]);
  const std::vector<int64_t> off = read_integers(offsets, offset_type, "cell offsets");
  if (lower_case(in_.word("CONNECTIVITY")) != "connectivity") in_.fail("CELLS: expected CONNECTIVITY");
  const VtkType conn_type = type_argument(arguments("CONNECTIVITY", 1, 1)[0]);
  const std::vector<int64_t> conn = read_integers(connectivity, conn_type, "cell connectivity");
  if (offsets > 0 && (off.front() != 0 || off.back() != int64_t(connectivity)))
    in_.fail("CELLS: offsets must run from 0 to the connectivity size " + std::to_string(connectivity));
  mesh_.cell_offsets.assign(off.begin(), off.end());
  if (offsets == 0) mesh_.cell_offsets.push_back(0);
  for (uint64_t i = 1; i < off.size(); ++i)
    if (off[i] < off[i - 1]) in_.fail("CELLS: offsets decrease at entry " + std::to_string(i));
  mesh_.connectivity.resize(conn.size());
  for (uint64_t i = 0; i < conn.size(); ++i) {
    if (conn[i] < 0) in_.fail("CELLS: negative point index at connectivity entry " + std::to_string(i));
    mesh_.connectivity[i] = uint64_t(conn[i]);
  }
}

void VtkReader::read_cell_types(const std::vector<std::string_view>& args) {
  if (have_types_) in_.fail("a second CELL_TYPES section");
  const std::vector<int64_t> types =
      read_integers(count_argument(args[0], "cell type count"), VtkType::i32, "cell types");
  mesh_.cell_types.resize(types.size());
  for (size_t i = 0; i < types.size(); ++i) {
    if (types[i] < 0 || types[i] > 255) in_.fail("cell " + std::to_string(i) + " has type " + std::to_string(types[i]));
    mesh_.cell_types[i] = uint8_t(types[i]);
  }
  have_types_ = true;
}

void VtkReader::start_attributes(const std::string& keyword, const std::vector<std::string_view>& args) {
  const bool points = keyword == "point_data";
  if (!have_points_ || (!points && !have_types_))
    in_.fail((points ? "POINT_DATA" : "CELL_DATA") + std::string(" before the points and cells"));
  const uint64_t expected = points ? mesh_.points.size() : mesh_.cell_types.size();
  attribute_tuples_ = count_argument(args[0], "attribute count");
  if (attribute_tuples_ != expected)
    in_.fail((points ? "POINT_DATA " : "CELL_DATA ") + std::to_string(attribute_tuples_) + ", expected " +
             std::to_string(expected));
  attributes_ = points ? &mesh_.point_data : &mesh_.cell_data;
}

void VtkReader::read_attribute(const std::string& keyword, const std::vector<std::string_view>& args) {
  if (!attributes_) in_.fail(keyword + " outside POINT_DATA / CELL_DATA");
  if (keyword == "scalars") return read_scalars(args);
  if (keyword == "texture_coordinates") {
    if (args.size() != 3) in_.fail("TEXTURE_COORDINATES: expected a name, a dimension and a type");
    return add_array(args[0], component_count(args[1]), type_argument(args[2]));
  }
  if (keyword == "color_scalars") {
    if (args.size() != 2) in_.fail("COLOR_SCALARS: expected a name and a component count");
    // Binary colour scalars are unsigned chars (0..255 for 0..1), ascii ones floats.
    add_array(args[0], component_count(args[1]), binary_ ? VtkType::u8 : VtkType::f32);
    if (binary_)
      for (double& v : attributes_->back().values) v /= 255.0;
    return;
  }
  if (args.size() != 2) in_.fail(keyword + ": expected a name and a type");
  add_array(args[0], keyword == "tensors" ? 9 : 3, type_argument(args[1]));
}

void VtkReader::read_scalars(const std::vector<std::string_view>& args) {
  if (args.size() < 2 || args.size() > 3) in_.fail("SCALARS: expected a name, a type and an optional component count");
  const VtkType type = type_argument(args[1]);
  const int components = args.size() == 3 ? component_count(args[2]) : 1;
  // LOOKUP_TABLE <name> usually follows; it names a colour table we do not use.
  const uint64_t before = in_.position();
  const auto next = in_.try_word();
  if (next && lower_case(*next) == "lookup_table")
    in_.skip_line();
  else
    in_.seek(before);
  add_array(args[0], components, type);
}

void VtkReader::add_array(std::string_view name, int components, VtkType type) {
  in_.require_fits(attribute_tuples_, uint64_t(components) * (binary_ ? type_size(type) : 1), std::string(name));
  MeshArray a;
  a.name = std::string(name);
  a.components = components;
  a.values = read_reals(attribute_tuples_ * uint64_t(components), type, "array values");
  attributes_->push_back(std::move(a));
}

void VtkReader::read_field(const std::vector<std::string_view>& args) {
  const uint64_t arrays = count_argument(args[1], "field array count");
  in_.require_fits(arrays, 4, "FIELD arrays");  // each needs at least a header line
  for (uint64_t i = 0; i < arrays; ++i) read_field_array();
}

// "name components tuples type" and the values. Dataset-level FIELD data (before POINT_DATA /
// CELL_DATA, e.g. TIME) is read and dropped.
void VtkReader::read_field_array() {
  std::string name(in_.word("field array name"));
  while (lower_case(name) == "metadata") {
    skip_metadata();
    name = in_.word("field array name");
  }
  if (name == "NULL_ARRAY") return in_.skip_line();
  const auto args = arguments("FIELD array " + name.substr(0, 40), 3, 3);
  const int components = component_count(args[0]);
  const uint64_t tuples = count_argument(args[1], "tuple count");
  const VtkType type = type_argument(args[2]);
  if (!attributes_) {
    in_.require_fits(tuples, uint64_t(components) * (binary_ ? type_size(type) : 1), name);
    read_reals(uint64_t(components) * tuples, type, "field values");
    return;
  }
  if (tuples != attribute_tuples_)
    in_.fail("field array '" + name + "' has " + std::to_string(tuples) + " tuples, expected " +
             std::to_string(attribute_tuples_));
  add_array(name, components, type);
}

void VtkReader::skip_lookup_table(const std::vector<std::string_view>& args) {
  const uint64_t entries = count_argument(args[1], "lookup table size");
  in_.require_fits(entries, 4, "LOOKUP_TABLE");  // 4 bytes (binary) or 4 numbers (ascii) each
  if (binary_)
    in_.take(4 * entries, "lookup table");
  else
    for (uint64_t i = 0; i < entries * 4; ++i) in_.real("lookup table entry");
}

// METADATA blocks (component names, information keys) end at the first blank line.
void VtkReader::skip_metadata() {
  in_.skip_line();
  while (in_.remaining() && !in_.at_blank_line()) in_.skip_line();
  in_.skip_line();
}

void VtkReader::finish() {
  if (!have_points_) in_.fail("no POINTS section");
  if (!have_cells_) in_.fail("no CELLS section");
  if (!have_types_) in_.fail("no CELL_TYPES section");
  const uint64_t cells = mesh_.cell_offsets.size() - 1;
  if (cells != mesh_.cell_types.size())
    in_.fail("CELLS has " + std::to_string(cells) + " cells, CELL_TYPES " + std::to_string(mesh_.cell_types.size()));
  split_polyhedra(mesh_, faces_in_connectivity(mesh_, in_.file()), in_.file());
  voxels_to_hexahedra(mesh_);
  if (pre_vtk91_lagrange_) lagrange_hexahedra_from_pre_vtk91_order(mesh_);
  split_quadratic_cells(mesh_, in_.file());
  check_mesh(mesh_, in_.file());
}

// ---------------------------------------------------------------------------------------------
// Writer.

class VtkWriter {
 public:
  explicit VtkWriter(const VtkLegacyWriteOptions& o) : options_(o) {}
  std::string write(const MeshData& mesh);

 private:
  void line(const std::string& text) { out_ += text + "\n"; }
  void reals(const std::vector<double>& values, bool as_float);
  void integers(const std::vector<int64_t>& values, bool as_int64);
  void end_block();
  void cells(const MeshData& mesh);
  void arrays(const char* section, uint64_t tuples, const std::vector<MeshArray>& arrays);

  VtkLegacyWriteOptions options_;
  std::string out_;
  int on_line_ = 0;  // ascii values on the current line
};

std::string VtkWriter::write(const MeshData& mesh) {
  line(options_.version51 ? "# vtk DataFile Version 5.1" : "# vtk DataFile Version 4.2");
  line("volstream unstructured mesh");
  line(options_.binary ? "BINARY" : "ASCII");
  line("DATASET UNSTRUCTURED_GRID");
  line("POINTS " + std::to_string(mesh.points.size()) + (options_.points_float64 ? " double" : " float"));
  std::vector<double> xyz;
  xyz.reserve(mesh.points.size() * 3);
  for (const vec3d& p : mesh.points) xyz.insert(xyz.end(), {p.x, p.y, p.z});
  reals(xyz, !options_.points_float64);
  cells(mesh);
  arrays("POINT_DATA", mesh.points.size(), mesh.point_data);
  arrays("CELL_DATA", mesh.cell_count(), mesh.cell_data);
  return std::move(out_);
}

void VtkWriter::end_block() {
  if (!options_.binary && on_line_ == 0) return;
  out_ += '\n';
  on_line_ = 0;
}

void VtkWriter::reals(const std::vector<double>& values, bool as_float) {
  for (double v : values) {
    if (options_.binary) {
      as_float ? append_value(out_, float(v), true) : append_value(out_, v, true);
      continue;
    }
    char buf[32];
    // Shortest representation that reads back to the same value.
    const auto r = as_float ? std::to_chars(buf, buf + sizeof buf, float(v)) : std::to_chars(buf, buf + sizeof buf, v);
    if (on_line_) out_ += ' ';
    out_.append(buf, r.ptr);
    if (++on_line_ == 9) end_block();
  }
  end_block();
}

void VtkWriter::integers(const std::vector<int64_t>& values, bool as_int64) {
  for (int64_t v : values) {
    if (options_.binary) {
      as_int64 ? append_value(out_, v, true) : append_value(out_, int32_t(v), true);
      continue;
    }
    if (on_line_) out_ += ' ';
    out_ += std::to_string(v);
    if (++on_line_ == 9) end_block();
  }
  end_block();
}

void VtkWriter::cells(const MeshData& mesh) {
  const uint64_t n = mesh.cell_count();
  if (options_.version51) {
    line("CELLS " + std::to_string(n + 1) + " " + std::to_string(mesh.connectivity.size()));
    line("OFFSETS vtktypeint64");
    integers(std::vector<int64_t>(mesh.cell_offsets.begin(), mesh.cell_offsets.end()), true);
    line("CONNECTIVITY vtktypeint64");
    integers(std::vector<int64_t>(mesh.connectivity.begin(), mesh.connectivity.end()), true);
  } else {
    // Version 4.2 stores 32-bit ints: refuse what would wrap.
    if (n + mesh.connectivity.size() > uint64_t(INT32_MAX) || mesh.points.size() > uint64_t(INT32_MAX))
      throw UsageError("mesh too large for a VTK 4.2 file; write version 5.1");
    std::vector<int64_t> lists;
    lists.reserve(n + mesh.connectivity.size());
    for (uint64_t c = 0; c < n; ++c) {
      lists.push_back(int64_t(mesh.cell_offsets[c + 1] - mesh.cell_offsets[c]));
      for (uint64_t k = mesh.cell_offsets[c]; k < mesh.cell_offsets[c + 1]; ++k)
        lists.push_back(int64_t(mesh.connectivity[k]));
    }
    line("CELLS " + std::to_string(n) + " " + std::to_string(lists.size()));
    integers(lists, false);
  }
  line("CELL_TYPES " + std::to_string(n));
  integers(std::vector<int64_t>(mesh.cell_types.begin(), mesh.cell_types.end()), false);
}

void VtkWriter::arrays(const char* section, uint64_t tuples, const std::vector<MeshArray>& list) {
  if (list.empty()) return;
  for (const MeshArray& a : list)
    if (a.name.empty() || a.name.find_first_of(" \t\r\n") != std::string::npos)
      throw UsageError("VTK legacy array names must be non-empty without whitespace: '" + a.name + "'");
  line(std::string(section) + " " + std::to_string(tuples));
  uint64_t field_arrays = 0;
  for (const MeshArray& a : list) {
    if (a.components == 1) {
      line("SCALARS " + a.name + " double 1");
      line("LOOKUP_TABLE default");
    } else if (a.components == 3) {
      line("VECTORS " + a.name + " double");
    } else {
      ++field_arrays;
      continue;
    }
    reals(a.values, false);
  }
  if (!field_arrays) return;
  line("FIELD FieldData " + std::to_string(field_arrays));
  for (const MeshArray& a : list) {
    if (a.components == 1 || a.components == 3) continue;
    line(a.name + " " + std::to_string(a.components) + " " + std::to_string(tuples) + " double");
    reals(a.values, false);
  }
}

}  // namespace

MeshData read_vtk_legacy(const fs::path& file) { return VtkReader(file).read(); }

void write_vtk_legacy(const fs::path& file, const MeshData& mesh, const VtkLegacyWriteOptions& options) {
  const std::string bytes = VtkWriter(options).write(mesh);
  write_file(file, bytes.data(), bytes.size());
}

}  // namespace vs
