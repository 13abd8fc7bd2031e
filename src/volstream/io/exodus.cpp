#include "volstream/io/exodus.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/parse_cursor.h"
#include "volstream/io/shared_library.h"
#include "volstream/io/solver_files.h"
#include "volstream/umesh/mesh_pieces.h"
#include "volstream/umesh/quadratic.h"

#ifdef VOLSTREAM_HAVE_NETCDF
#include <netcdf.h>
#endif

namespace vs {
namespace fs = std::filesystem;

#ifndef VOLSTREAM_HAVE_NETCDF

bool exodus_supported() { return false; }
struct ExodusFile::Impl {};
ExodusFile::ExodusFile(const fs::path& file, const std::vector<std::string>&) {
  input_error(file.string(),
              "this volstream was built without the NetCDF library, which Exodus II files need "
              "(Debian: apt-get install libnetcdf-dev, then build again)");
}
ExodusFile::~ExodusFile() = default;
size_t ExodusFile::step_count() const { return 0; }
double ExodusFile::step_time(size_t) const { return 0; }
MeshData ExodusFile::read_step(size_t) { return {}; }
std::string ExodusFile::summary() const { return {}; }

#else

bool exodus_supported() { return true; }

namespace {

// The NetCDF functions the reader calls, from the library opened at the first Exodus file
// (io/shared_library.h: linked, it cost every command ~20 ms of start).
// clang-format off
#define VOLSTREAM_NETCDF_FUNCTIONS(X)                                                        \
  X(nc_open) X(nc_close) X(nc_strerror) X(nc_inq_format) X(nc_inq_varid) X(nc_inq_dimid)     \
  X(nc_inq_dimlen) X(nc_inq_varndims) X(nc_inq_vardimid) X(nc_inq_attlen) X(nc_get_att_text) \
  X(nc_get_var_text) X(nc_get_var_double) X(nc_get_var_longlong) X(nc_get_vara_double)
// clang-format on
VOLSTREAM_LIBRARY_CALLS(NetcdfCalls, VOLSTREAM_NETCDF_FUNCTIONS);

const NetcdfCalls& netcdf() {
  return hdf5_reader_calls<NetcdfCalls>(VOLSTREAM_NETCDF_SONAME,
                                        "Exodus II files need it (Debian: apt-get install libnetcdf-dev)");
}

// An element type as Exodus names it, the node count its block gives, and what it is in VTK:
// the cell type and, for each VTK node, the Exodus node (0-based) that is it.
struct ElementKind {
  const char* family;  // the name's start (Exodus writers add the node count or not: HEX, HEX8)
  int nodes;
  uint8_t vtk_type;
  std::vector<int> vtk_from_exodus;  // empty: the same order
};

// Exodus orders a quadratic hexahedron's and wedge's mid-edge nodes bottom, vertical, top; its
// wedge's first triangle faces the second, as EnSight's (io/solver_files.h). A HEX27's centre is
// its node 20, then the faces -z, +z, -x, +x, -y, +y; VTK has the faces -x, +x, -y, +y, -z, +z,
// then the centre. (SEACAS's Ioss element tables.)
const std::vector<ElementKind>& element_kinds() {
  static const std::vector<ElementKind> kinds = {
      {"TET", 4, 10, {}},
      {"TET", 10, uint8_t(QuadraticCell::tet10), {}},
      {"HEX", 8, 12, {}},
      {"HEX", 20, uint8_t(QuadraticCell::hex20), {kHex20BottomVerticalTop.begin(), kHex20BottomVerticalTop.end()}},
      {"HEX", 27, uint8_t(QuadraticCell::hex27), {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 16, 17,
                                                  18, 19, 12, 13, 14, 15, 23, 24, 25, 26, 21, 22, 20}},
      {"WEDGE", 6, 13, {kWedgeFacingInward.begin(), kWedgeFacingInward.end()}},
      {"WEDGE",
       15,
       uint8_t(QuadraticCell::wedge15),
       {kWedge15FacingInwardBottomVerticalTop.begin(), kWedge15FacingInwardBottomVerticalTop.end()}},
      {"PYRA", 5, 14, {}},
      {"PYRA", 13, uint8_t(QuadraticCell::pyramid13), {}},
  };
  return kinds;
}

// Element families that are not volumes: blocks of them are left out.
bool is_lower_dimensional(const std::string& type) {
  static const char* const kFamilies[] = {"SHELL", "QUAD",   "TRI",    "BEAM",  "BAR",  "TRUSS",  "ROD",
                                          "EDGE",  "SPHERE", "CIRCLE", "POINT", "NODE", "SPRING", "NSIDED"};
  return std::any_of(std::begin(kFamilies), std::end(kFamilies), [&](const char* f) { return type.rfind(f, 0) == 0; });
}

std::string trimmed_upper(std::string s) {
  s = trimmed_name(std::move(s));
  for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

uint64_t padded4(uint64_t n) { return (n + 3) / 4 * 4; }

uint64_t netcdf_type_size(uint32_t type, const ParseCursor& c) {
  static const uint8_t kSizes[] = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};  // NC_BYTE (1) .. NC_UINT64 (11)
  if (type == 0 || type >= std::size(kSizes)) c.fail("a variable of unknown NetCDF type " + std::to_string(type));
  return kSizes[type];
}

// The bytes a classic NetCDF file (CDF-1, CDF-2 or CDF-5; its header at the front of `c`) needs
// for all its variables' data, from the offsets and shapes its header gives; 0 for a file whose
// record count is left open (streaming). The NetCDF library reads a classic file cut short as
// zeros past its end, so the reader compares this with the file's size.
uint64_t classic_netcdf_data_end(ParseCursor& c) {
  const char* magic = c.take(4, "magic number");
  const int version = magic[3];
  const bool wide_counts = version == 5;  // CDF-5: 64-bit counts; CDF-2 and -5: 64-bit offsets
  auto count = [&] { return wide_counts ? c.binary<uint64_t>(true, "count") : c.binary<uint32_t>(true, "count"); };
  auto skip_name = [&] { c.take(padded4(count()), "name"); };
  auto each = [&](uint32_t tag, auto&& item) {
    const uint32_t t = c.binary<uint32_t>(true, "list tag");
    const uint64_t n = count();
    if (t == 0 && n == 0) return;
    if (t != tag) c.fail("a NetCDF header list of an unknown kind");
    c.require_fits(n, 8, "NetCDF header entries");
    for (uint64_t i = 0; i < n; ++i) item();
  };
  auto skip_attributes = [&] {
    each(0x0C, [&] {
      skip_name();
      const uint64_t type_size = netcdf_type_size(c.binary<uint32_t>(true, "attribute type"), c);
      const uint64_t n = count();
      c.require_fits(n, type_size, "attribute values");
      c.take(padded4(n * type_size), "attribute values");
    });
  };
  const uint64_t records = count();
  if (records == (wide_counts ? ~uint64_t(0) : 0xFFFFFFFFu)) return 0;
  std::vector<uint64_t> dims;
  each(0x0A, [&] {
    skip_name();
    dims.push_back(count());
  });
  skip_attributes();
  struct Variable {
    uint64_t begin, bytes;
    bool record;
  };
  std::vector<Variable> vars;
  each(0x0B, [&] {
    skip_name();
    const uint64_t rank = count();
    c.require_fits(rank, 4, "variable dimensions");
    Variable v{0, 1, false};
    for (uint64_t d = 0; d < rank; ++d) {
      const uint64_t id = count();
      if (id >= dims.size()) c.fail("a variable of a dimension the header does not define");
      if (d == 0 && dims[id] == 0)
        v.record = true;
      else if (__builtin_mul_overflow(v.bytes, dims[id], &v.bytes))
        c.fail("a variable larger than any file");
    }
    skip_attributes();
    if (__builtin_mul_overflow(v.bytes, netcdf_type_size(c.binary<uint32_t>(true, "variable type"), c), &v.bytes))
      c.fail("a variable larger than any file");
    count();  // vsize: capped for large variables, so the shape's size is used
    v.begin = version == 1 ? c.binary<uint32_t>(true, "offset") : c.binary<uint64_t>(true, "offset");
    vars.push_back(v);
  });
  uint64_t record_bytes = 0, end = 0;
  const size_t record_vars =
      size_t(std::count_if(vars.begin(), vars.end(), [](const Variable& v) { return v.record; }));
  for (const Variable& v : vars)
    if (v.record) record_bytes += record_vars == 1 ? v.bytes : padded4(v.bytes);
  for (const Variable& v : vars) {
    uint64_t last = v.begin;
    if (v.record && records > 0 &&
        (__builtin_mul_overflow(records - 1, record_bytes, &last) || __builtin_add_overflow(last, v.begin, &last)))
      c.fail("records larger than any file");
    if (v.record && records == 0) continue;
    if (__builtin_add_overflow(last, v.bytes, &last)) c.fail("a variable past the end of any file");
    end = std::max(end, last);
  }
  return end;
}

// "CDF" and version 1, 2 or 5: the classic formats (NetCDF-4 files are HDF5 files).
bool is_classic_netcdf(const std::string& file) {
  char magic[4] = {};
  std::ifstream(file, std::ios::binary).read(magic, 4);
  return magic[0] == 'C' && magic[1] == 'D' && magic[2] == 'F' && (magic[3] == 1 || magic[3] == 2 || magic[3] == 5);
}

// InputError unless `file`, a classic NetCDF file, holds all its variables' data.
void check_classic_netcdf_size(const std::string& file) {
  const uint64_t size = file_size_checked(file);
  for (uint64_t prefix = std::min<uint64_t>(size, 1 << 20);; prefix = std::min(size, prefix * 8)) {
    std::string head(prefix, '\0');
    std::ifstream in(file, std::ios::binary);
    in.read(head.data(), std::streamsize(prefix));
    ParseCursor c(std::move(head), file);
    try {
      const uint64_t end = classic_netcdf_data_end(c);
      input_check(
          end <= size, file,
          "truncated: its variables need " + std::to_string(end) + " bytes, the file has " + std::to_string(size));
      return;
    } catch (const InputError& e) {
      const std::string why = e.what();
      if (prefix < size) continue;  // the header goes on past the prefix read
      throw InputError(file, why.starts_with("truncated") ? why : "truncated in its NetCDF header (" + why + ")");
    }
  }
}

}  // namespace

struct ExodusFile::Impl {
  mutable SplitMemo quadratic_split;  // the last step's, for the next
  struct Block {
    int index = 0;  // 1-based, as in the variable names (connect3, vals_elem_var2eb3)
    int64_t id = 0;
    std::string name;  // eb_names' ("" where it has none)
    std::string type;
    uint64_t count = 0;
    bool kept = false;
  };
  using ArrayOfVariables = VariableGroup;  // nodal or element variables as arrays

  std::string file;
  int ncid = -1;
  std::string format;
  std::vector<Block> blocks;
  std::vector<double> times;
  MeshData topology;                // points and kept cells, VTK order; no data
  std::vector<std::string> wanted;  // the element blocks to read, by name or id (empty: all)
  std::vector<bool> kept_nodes;     // the nodes the blocks read use, where some blocks are not read (else empty)
  std::vector<ArrayOfVariables> nodal, element;
  bool nodal_in_one_variable = false;  // old files: vals_nod_var[time][variable][node]
  std::vector<std::string> left_out;   // element variables left out, or without values on some block

  ~Impl() {
    if (ncid >= 0) netcdf().nc_close(ncid);
  }

  void check(int status, const std::string& what) const {
    if (status != NC_NOERR) input_error(file, what + ": " + netcdf().nc_strerror(status));
  }
  bool has_variable(const std::string& name) const {
    int id = 0;
    return netcdf().nc_inq_varid(ncid, name.c_str(), &id) == NC_NOERR;
  }
  int variable(const std::string& name) const {
    int id = 0;
    check(netcdf().nc_inq_varid(ncid, name.c_str(), &id), "no variable " + name);
    return id;
  }
  // A dimension's length; `fallback` when the file has no such dimension (-1: refuse).
  size_t dimension(const std::string& name, int64_t fallback = -1) const {
    int id = 0;
    if (netcdf().nc_inq_dimid(ncid, name.c_str(), &id) != NC_NOERR) {
      input_check(fallback >= 0, file, "not an Exodus II file: no dimension " + name);
      return size_t(fallback);
    }
    size_t length = 0;
    check(netcdf().nc_inq_dimlen(ncid, id, &length), "dimension " + name);
    return length;
  }
  size_t variable_size(int var) const {
    int rank = 0;
    check(netcdf().nc_inq_varndims(ncid, var, &rank), "variable shape");
    std::vector<int> dims(size_t(std::max(rank, 0)));
    check(netcdf().nc_inq_vardimid(ncid, var, dims.data()), "variable shape");
    size_t size = 1;
    for (int d : dims) {
      size_t length = 0;
      check(netcdf().nc_inq_dimlen(ncid, d, &length), "variable shape");
      size = product(size, length);
    }
    return size;
  }
  // a * b, refused where it overflows (dimensions of a damaged file).
  size_t product(size_t a, size_t b) const {
    size_t p = 0;
    input_check(!__builtin_mul_overflow(a, b, &p), file, "a variable larger than any file");
    return p;
  }
  std::vector<double> doubles(const std::string& name, size_t expected) const {
    const int var = variable(name);
    input_check(variable_size(var) == expected, file,
                name + " holds " + std::to_string(variable_size(var)) + " values, not " + std::to_string(expected));
    std::vector<double> values(expected);
    if (expected) check(netcdf().nc_get_var_double(ncid, var, values.data()), "reading " + name);
    return values;
  }
  std::string text_attribute(int var, const char* name) const {
    size_t length = 0;
    if (netcdf().nc_inq_attlen(ncid, var, name, &length) != NC_NOERR) return {};
    std::string s(length, '\0');
    check(netcdf().nc_get_att_text(ncid, var, name, s.data()), std::string("attribute ") + name);
    return s;
  }
  // The rows of a char variable [count][len_name] (variable names), "" for a missing variable.
  std::vector<std::string> names(const std::string& var_name, size_t count) const {
    std::vector<std::string> out(count);
    if (!count || !has_variable(var_name)) return out;
    const int var = variable(var_name);
    const size_t size = variable_size(var);
    input_check(size % count == 0, file, var_name + " is not " + std::to_string(count) + " names");
    std::string all(size, '\0');
    check(netcdf().nc_get_var_text(ncid, var, all.data()), "reading " + var_name);
    const size_t width = size / count;
    for (size_t i = 0; i < count; ++i) out[i] = trimmed_name(all.substr(i * width, width));
    return out;
  }

  void open(const fs::path& path) {
    file = path.string();
    // A classic file's header is checked before the library reads it (see above).
    if (is_classic_netcdf(file)) check_classic_netcdf_size(file);
    check(netcdf().nc_open(file.c_str(), NC_NOWRITE, &ncid), "not a NetCDF file (Exodus II files are)");
    int f = 0;
    check(netcdf().nc_inq_format(ncid, &f), "format");
    format = f == NC_FORMAT_CLASSIC        ? "classic"
             : f == NC_FORMAT_64BIT_OFFSET ? "64-bit offset"
             : f == NC_FORMAT_64BIT_DATA   ? "64-bit data"
                                           : "NetCDF-4";
    const size_t dims = dimension("num_dim");
    input_check(dims == 3, file, "a " + std::to_string(dims) + "D Exodus mesh: volstream renders volumes (num_dim 3)");
    read_points();
    read_blocks();
    if (!wanted.empty()) kept_nodes = drop_unused_points(topology);
    read_times();
    nodal = group_vector_variables(names("name_nod_var", dimension("num_nod_var", 0)));
    element = group_vector_variables(names("name_elem_var", dimension("num_elem_var", 0)));
    note_partial_element_arrays();
    nodal_in_one_variable = !nodal.empty() && has_variable("vals_nod_var");
  }

  bool has_values(const Block& b, int v) const {
    return has_variable("vals_elem_var" + std::to_string(v + 1) + "eb" + std::to_string(b.index));
  }

  // Solvers often write an element variable on some blocks only (a material's stress): it is
  // NaN, no data, on the others, and the summary says where; one on no volume block is left out.
  void note_partial_element_arrays() {
    if (dimension("time_step", 0) == 0) return;  // no values at all: nothing is read
    std::erase_if(element, [&](const ArrayOfVariables& a) {
      std::vector<std::string> without;
      for (const Block& b : blocks) {
        if (!b.kept) continue;
        bool all = true;
        for (int c = 0; c < a.components; ++c) all = all && has_values(b, a.first + c);
        if (!all) without.push_back(block_name(b));
      }
      const bool anywhere = std::any_of(blocks.begin(), blocks.end(), [&](const Block& b) {
        for (int c = 0; c < a.components; ++c)
          if (b.kept && has_values(b, a.first + c)) return true;
        return false;
      });
      if (!anywhere) {  // `without` is empty where no volume block is read
        left_out.push_back(a.name + " left out (no values on " + (without.empty() ? "a block read" : without.front()) +
                           ")");
        return true;
      }
      for (const std::string& b : without) left_out.push_back(a.name + " no data (NaN) on " + b);
      return false;
    });
  }

  void read_points() {
    const size_t n = dimension("num_nodes");
    input_check(n > 0, file, "an Exodus mesh without nodes");
    std::array<std::vector<double>, 3> axes;
    if (has_variable("coordx")) {
      const char* kNames[] = {"coordx", "coordy", "coordz"};
      for (int a = 0; a < 3; ++a) axes[size_t(a)] = doubles(kNames[a], n);
    } else {
      const std::vector<double> all = doubles("coord", product(3, n));  // coord[dimension][node]
      for (size_t a = 0; a < 3; ++a)
        axes[a].assign(all.begin() + ptrdiff_t(a * n), all.begin() + ptrdiff_t((a + 1) * n));
    }
    topology.points.resize(n);
    for (size_t i = 0; i < n; ++i) topology.points[i] = vec3d(axes[0][i], axes[1][i], axes[2][i]);
  }

  void read_blocks() {
    const size_t count = dimension("num_el_blk");
    std::vector<long long> ids(count, 0);
    if (count && has_variable("eb_prop1")) {
      const int var = variable("eb_prop1");
      input_check(variable_size(var) == count, file, "eb_prop1 is not one id per element block");
      check(netcdf().nc_get_var_longlong(ncid, var, ids.data()), "reading eb_prop1");
    }
    const std::vector<std::string> block_names = names("eb_names", count);
    topology.cell_offsets = {0};
    for (size_t b = 0; b < count; ++b) {
      Block block;
      block.index = int(b + 1);
      block.id = ids[b] ? ids[b] : block.index;
      block.name = block_names[b];
      const std::string suffix = std::to_string(block.index);
      block.count = dimension("num_el_in_blk" + suffix, 0);
      if (block.count && is_wanted(block)) read_block(block, suffix);
      blocks.push_back(block);
    }
    for (const std::string& w : wanted)
      if (std::none_of(blocks.begin(), blocks.end(), [&](const Block& b) { return answers_to(b, w); })) {
        std::vector<std::string> labels;
        for (const Block& b : blocks) labels.push_back(block_label(b));
        input_error(file, "no element block '" + w + "' in this file (its blocks: " + joined(labels) + ")");
      }
    // A rank file of a parallel run may hold none of the blocks asked for (the series checks the
    // joined mesh).
    input_check(topology.cell_count() > 0 || !wanted.empty(), file,
                "no volume elements (only surface, line or point element blocks)");
  }

  std::string block_name(const Block& b) const { return "element block " + std::to_string(b.id); }
  // "10" or "10 (fluid)": the block's id and its name, for messages.
  static std::string block_label(const Block& b) {
    return std::to_string(b.id) + (b.name.empty() ? "" : " (" + b.name + ")");
  }
  static bool answers_to(const Block& b, const std::string& w) { return w == b.name || w == std::to_string(b.id); }
  bool is_wanted(const Block& b) const {
    return wanted.empty() ||
           std::any_of(wanted.begin(), wanted.end(), [&](const std::string& w) { return answers_to(b, w); });
  }

  void read_block(Block& block, const std::string& suffix) {
    const int var = variable("connect" + suffix);
    block.type = trimmed_upper(text_attribute(var, "elem_type"));
    const size_t nodes = dimension("num_nod_per_el" + suffix);
    if (is_lower_dimensional(block.type)) return;
    const auto& kinds = element_kinds();
    const auto kind = std::find_if(kinds.begin(), kinds.end(), [&](const ElementKind& k) {
      return block.type.rfind(k.family, 0) == 0 && size_t(k.nodes) == nodes;
    });
    if (kind == kinds.end())
      input_error(file, block_name(block) + ": unsupported element type " + block.type + " with " +
                            std::to_string(nodes) + " nodes (TETRA4/10, HEX8/20/27, WEDGE6/15, PYRAMID5/13 are read)");
    input_check(variable_size(var) == product(block.count, nodes), file,
                block_name(block) + ": connect" + suffix + " is not " + std::to_string(block.count) + " x " +
                    std::to_string(nodes) + " node indices");
    std::vector<long long> connect(product(block.count, nodes));
    check(netcdf().nc_get_var_longlong(ncid, var, connect.data()), "reading connect" + suffix);
    const long long points = (long long)topology.points.size();
    for (uint64_t e = 0; e < block.count; ++e) {
      const long long* nodes_of_e = connect.data() + e * nodes;
      for (size_t k = 0; k < nodes; ++k) {
        const long long node = nodes_of_e[kind->vtk_from_exodus.empty() ? k : size_t(kind->vtk_from_exodus[k])];
        if (!(node >= 1 && node <= points))
          input_error(file, block_name(block) + ", element " + std::to_string(e + 1) + ": node " +
                                std::to_string(node) + " out of range 1.." + std::to_string(points));
        topology.connectivity.push_back(uint64_t(node - 1));
      }
      topology.cell_types.push_back(kind->vtk_type);
      topology.cell_offsets.push_back(topology.connectivity.size());
    }
    block.kept = true;
  }

  void read_times() {
    const size_t steps = dimension("time_step", 0);
    if (steps == 0) {
      times = {0.0};
      return;
    }
    times = doubles("time_whole", steps);
    for (double t : times) input_check(std::isfinite(t), file, "a time step at a time that is not finite");
  }

  // Values of one variable at a step: [time_step][count] in `name`, or row `row` of
  // [time_step][rows][count].
  std::vector<double> step_values(const std::string& name, size_t step, size_t count, int row = -1) const {
    const int var = variable(name);
    std::vector<double> v(count);
    if (row < 0) {
      input_check(variable_size(var) == product(times.size(), count), file,
                  name + " is not one value per step and entry");
      const size_t start[2] = {step, 0}, extent[2] = {1, count};
      check(netcdf().nc_get_vara_double(ncid, var, start, extent, v.data()), "reading " + name);
    } else {
      const size_t start[3] = {step, size_t(row), 0}, extent[3] = {1, 1, count};
      input_check(variable_size(var) % product(times.size(), count) == 0, file, name + " is not one value per node");
      check(netcdf().nc_get_vara_double(ncid, var, start, extent, v.data()), "reading " + name);
    }
    return v;
  }

  std::vector<double> nodal_values(int variable_index, size_t step) const {
    const size_t n = dimension("num_nodes");
    std::vector<double> all = nodal_in_one_variable
                                  ? step_values("vals_nod_var", step, n, variable_index)
                                  : step_values("vals_nod_var" + std::to_string(variable_index + 1), step, n);
    if (kept_nodes.empty()) return all;
    std::vector<double> kept;
    for (size_t node = 0; node < all.size(); ++node)
      if (kept_nodes[node]) kept.push_back(all[node]);
    return kept;
  }

  std::vector<double> element_values(int variable_index, size_t step) const {
    std::vector<double> out;
    for (const Block& b : blocks) {
      if (!b.kept) continue;
      if (!has_values(b, variable_index)) {  // no data there
        out.insert(out.end(), b.count, std::nan(""));
        continue;
      }
      const std::string name = "vals_elem_var" + std::to_string(variable_index + 1) + "eb" + std::to_string(b.index);
      const std::vector<double> v = step_values(name, step, b.count);
      out.insert(out.end(), v.begin(), v.end());
    }
    return out;
  }

  // `arrays` interleaved as MeshArrays, from `values(variable index)`.
  template <class Values>
  static std::vector<MeshArray> interleaved(const std::vector<ArrayOfVariables>& arrays, Values values) {
    std::vector<MeshArray> out;
    for (const ArrayOfVariables& a : arrays) {
      MeshArray m{a.name, a.components, {}};
      for (int c = 0; c < a.components; ++c) {
        const std::vector<double> v = values(a.first + c);
        if (m.values.empty()) m.values.resize(v.size() * size_t(a.components));
        for (size_t i = 0; i < v.size(); ++i) m.values[i * size_t(a.components) + size_t(c)] = v[i];
      }
      out.push_back(std::move(m));
    }
    return out;
  }

  // Step s's point and cell data into m.
  void read_values(size_t s, MeshData& m) const {
    if (dimension("time_step", 0) == 0) return;  // a mesh alone
    m.point_data = interleaved(nodal, [&](int v) { return nodal_values(v, s); });
    m.cell_data = interleaved(element, [&](int v) { return element_values(v, s); });
  }

  // Every read the steps make, and nothing else (read_in_child_first).
  void read_all_values() const {
    MeshData scratch;
    for (size_t s = 0; s < times.size(); ++s) read_values(s, scratch);
  }

  MeshData step(size_t s) const {
    input_check(s < times.size(), file, "no time step " + std::to_string(s));
    MeshData m = topology;
    if (m.cell_count() == 0) return m;  // none of the blocks asked for are in this rank file
    read_values(s, m);
    split_quadratic_cells(m, file, times.size() > 1 ? &quadratic_split : nullptr);
    check_mesh(m, file);
    return m;
  }

  std::string summary() const {
    std::string s = format;
    std::map<std::string, uint64_t> counts;
    for (const Block& b : blocks)
      if (b.kept) counts[b.type] += b.count;
    const char* sep = ": ";
    for (const auto& [type, n] : counts) {
      s += sep + type + " x " + std::to_string(n);
      sep = ", ";
    }
    if (!wanted.empty()) {
      s += "; blocks read:";
      for (const Block& b : blocks)
        if (b.kept) s += " " + block_label(b);
    }
    for (const std::string& a : left_out) s += "; element variable " + a;
    return s;
  }
};

ExodusFile::ExodusFile(const fs::path& file, const std::vector<std::string>& blocks) : impl_(std::make_unique<Impl>()) {
  file_size_checked(file);  // a regular file (a FIFO would block every read below)
  impl_->wanted = blocks;
  netcdf();                               // loaded here, not in the child below (read_in_child_first)
  if (!is_classic_netcdf(file.string()))  // classic files are read by NetCDF's own code
    read_in_child_first(file.string(), "NetCDF-4", [&] {
      Impl first;
      first.wanted = blocks;
      first.open(file);
      first.read_all_values();
    });
  impl_->open(file);
}
ExodusFile::~ExodusFile() = default;
size_t ExodusFile::step_count() const { return impl_->times.size(); }
double ExodusFile::step_time(size_t step) const { return impl_->times.at(step); }
MeshData ExodusFile::read_step(size_t step) { return impl_->step(step); }
std::string ExodusFile::summary() const { return impl_->summary(); }

#endif

}  // namespace vs
