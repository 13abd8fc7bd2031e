#include "volstream/io/fluent.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <string_view>

#include "volstream/core/error.h"
#include "volstream/core/release.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/byte_order.h"
#include "volstream/io/parse_cursor.h"
#include "volstream/umesh/polyhedra.h"

namespace vs {
namespace fs = std::filesystem;

namespace {

// Fluent's files are lists in parentheses: "(INDEX BODY...)", BODY holding a header list of
// numbers and, for the mesh and data sections, a list of values, as text or as bytes (section
// indices of four digits, 2xxx single and 3xxx double precision, end with "End of Binary Section
// INDEX)"). ParseCursor's binary reads and size checks, with the list syntax on top: tokens end
// at parentheses as well as at spaces. Syntax failures name the offset.
class Cursor : public ParseCursor {
 public:
  using ParseCursor::ParseCursor;

  [[noreturn]] void fail(const std::string& what) const {
    ParseCursor::fail("offset " + std::to_string(position()) + ": " + what);
  }

  bool at_end() {
    skip_space();
    return remaining() == 0;
  }
  bool peek(char c) {
    skip_space();
    return !rest().empty() && rest().front() == c;
  }
  void expect(char c, const char* where) {
    if (!peek(c)) fail(std::string("expected '") + c + "' " + where + (remaining() ? "" : " (the file ends)"));
    seek(position() + 1);
  }

  // A number as the format writes it: hexadecimal in the case file's headers and lists,
  // decimal in section indices and in the data file's headers.
  uint64_t number(int base, const char* what) {
    skip_space();
    const std::string_view r = rest();
    size_t n = 0;
    uint64_t v = 0;
    for (int d; n < r.size() && (d = digit(r[n], base)) >= 0; ++n) {
      if (v > (uint64_t(1) << 48)) fail(std::string(what) + " is too large");
      v = v * uint64_t(base) + uint64_t(d);
    }
    if (n == 0) fail(std::string("expected ") + what);
    seek(position() + n);
    return v;
  }
  double real(const char* what) {
    const std::string_view text = token();
    double v = 0;
    const char* first = text.data() + (text.size() > 1 && text[0] == '+' ? 1 : 0);
    const auto [end, ec] = std::from_chars(first, text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size()) {
      seek(position() - text.size());
      fail(std::string("expected a number (") + what + ")");
    }
    return v;
  }
  // A word of a zone's name: up to a space or a parenthesis.
  std::string word(const char* what) {
    const std::string_view w = token();
    if (w.empty()) fail(std::string("expected ") + what);
    return std::string(w);
  }

  template <typename T>
  T binary(const char* what) {
    return ParseCursor::binary<T>(false, what);  // Fluent writes little-endian on every machine we meet
  }
  void skip_bytes(uint64_t bytes, const char* what) { take(bytes, what); }

  // Past the ')' that closes a list whose '(' is behind us; strings in double quotes (the
  // settings' values) may hold parentheses of their own.
  void skip_list() {
    int depth = 1;
    while (remaining()) {
      const char c = next_char();
      if (c == '"')
        skip_string();
      else if (c == '(')
        ++depth;
      else if (c == ')' && --depth == 0)
        return;
    }
    fail("unbalanced parentheses: a list is not closed before the end of the file");
  }
  // The end of a binary section: its values' ')', then "End of Binary Section INDEX)".
  void end_binary_section(int index) {
    expect(')', "after the binary values");
    skip_space();
    if (!rest().starts_with(kEndOfBinary)) fail("expected \"End of Binary Section " + std::to_string(index) + ")\"");
    seek(position() + kEndOfBinary.size());
    if (number(10, "the section index") != uint64_t(index))
      fail("the binary section " + std::to_string(index) + " ends as another");
    expect(')', "closing the binary section");
  }
  // Past the end of an unknown binary section, whose values' size we do not know: the first
  // "End of Binary Section" (as VTK's reader finds it), then its ')'.
  void skip_unknown_binary_section(int index) {
    if (!skip_past(kEndOfBinary)) fail("binary section " + std::to_string(index) + " has no end");
    number(10, "the section index");
    expect(')', "closing the binary section");
  }

 private:
  static constexpr std::string_view kEndOfBinary = "End of Binary Section";

  static int digit(char c, int base) {
    if (c >= '0' && c <= '9') return c - '0';
    if (base == 16 && c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (base == 16 && c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  }
  char next_char() {
    const char c = rest().front();
    seek(position() + 1);
    return c;
  }
  // Up to a space or a parenthesis (empty at either, or at the end).
  std::string_view token() {
    skip_space();
    const std::string_view r = rest();
    size_t n = 0;
    while (n < r.size() && !std::isspace(static_cast<unsigned char>(r[n])) && r[n] != '(' && r[n] != ')') ++n;
    seek(position() + n);
    return r.substr(0, n);
  }
  void skip_string() {
    while (remaining()) {
      const char c = next_char();
      if (c == '\\' && remaining())
        next_char();
      else if (c == '"')
        return;
    }
    fail("a string in double quotes is not closed before the end of the file");
  }
};

bool is_binary_index(int index) { return index >= 1000; }
bool is_double_index(int index) { return index / 1000 == 3; }

// A section's header list "(a b c ...)" of hexadecimal (case file) or decimal (data file)
// numbers, as many as it has.
std::vector<uint64_t> header_numbers(Cursor& in, int base) {
  in.expect('(', "opening the section's header");
  std::vector<uint64_t> v;
  while (!in.peek(')')) {
    if (v.size() == 8) in.fail("a section header of more than 8 numbers");
    v.push_back(in.number(base, "a header number"));
  }
  in.expect(')', "closing the section's header");
  return v;
}

// Fluent's element types (section 12), as `info` names them.
constexpr int kMixed = 0, kTriangle = 1, kQuad = 3, kPolyhedron = 7;
const char* element_name(int type) {
  static const char* const kNames[] = {"mixed", "triangle", "tet", "quad", "hex", "pyramid", "wedge", "polyhedron"};
  return kNames[type];
}

struct Range {
  uint64_t first = 0, last = 0;  // 1-based, inclusive
  uint64_t count() const { return last - first + 1; }
};

struct CellZone {
  uint64_t id = 0;
  Range cells;
};

// The mesh a case file describes.
struct CaseMesh {
  uint64_t node_count = 0, cell_count = 0, face_count = 0;  // as declared (zone 0)
  bool nodes_declared = false, cells_declared = false;
  std::vector<vec3d> nodes;
  std::vector<uint8_t> cell_types;  // Fluent's element type per cell (0: not in a zone yet)
  std::vector<CellZone> cell_zones;
  std::vector<FaceCells> faces;  // c0 and c1 of each face
  std::vector<uint64_t> face_offsets{0};
  std::vector<FaceIndex> face_vertices;  // 0-based nodes
  std::map<uint64_t, std::string> zone_names;
};

// Cell zone z's name (sections 39 and 45), or its id where the case names it not.
std::string zone_name(const CaseMesh& m, size_t z) {
  const auto name = m.zone_names.find(m.cell_zones[z].id);
  return name != m.zone_names.end() ? name->second : std::to_string(m.cell_zones[z].id);
}

class CaseReader {
 public:
  explicit CaseReader(const fs::path& file) : in_(read_file_inflating(file), file.string()) {}

  CaseMesh read() {
    while (!in_.at_end()) section();
    check_complete();
    return std::move(mesh_);
  }

 private:
  void section() {
    in_.expect('(', "opening a section");
    const int index = int(in_.number(10, "a section index"));
    switch (index % 1000) {
      case 2:
        return dimension();
      case 10:
        return nodes(index);
      case 12:
        return cells(index);
      case 13:
        return faces(index);
      case 39:
      case 45:
        return zone_name(index);
      case 58:
      case 59:
        in_.fail("section " + std::to_string(index) + " (" + (index % 1000 == 58 ? "cell" : "face") +
                 " tree): meshes with hanging-node adaption are not read");
      case 61:
        in_.fail("section " + std::to_string(index) +
                 " (interface face parents): non-conformal interfaces are not read");
      default:
        return skip(index);
    }
  }

  void skip(int index) {
    if (is_binary_index(index))
      in_.skip_unknown_binary_section(index);
    else
      in_.skip_list();
  }

  void dimension() {
    const uint64_t d = in_.number(10, "the dimension");
    if (d != 3) in_.fail("a " + std::to_string(d) + "D case: only 3D cases are read");
    in_.expect(')', "closing the dimension section");
  }

  // Declarations (zone 0) give the counts; a zone's range must lie inside them.
  Range zone_range(const std::vector<uint64_t>& h, uint64_t declared, const char* what) {
    const Range r{h[1], h[2]};
    if (r.first < 1 || r.last < r.first || r.last > declared)
      in_.fail(std::string(what) + " " + std::to_string(r.first) + ".." + std::to_string(r.last) +
               " outside the declared 1.." + std::to_string(declared));
    return r;
  }
  // A declared count must be one the file could describe (each item at least `bytes_each`
  // bytes: a node's coordinates 6, "0 0 0\n").
  uint64_t declared_count(uint64_t count, uint64_t bytes_each, const char* what) {
    if (count > in_.size() / bytes_each)
      in_.fail(std::string("declares ") + std::to_string(count) + " " + what + ", more than a file of " +
               std::to_string(in_.size()) + " bytes holds");
    return count;
  }

  void nodes(int index) {
    const std::vector<uint64_t> h = header_numbers(in_, 16);
    if (h.size() < 4) in_.fail("a node section header of fewer than 4 numbers");
    if (h.size() >= 5 && h[4] != 3) in_.fail("nodes of dimension " + std::to_string(h[4]) + ": only 3D cases are read");
    if (h[0] == 0) {
      mesh_.node_count = declared_count(h[2], 6, "nodes");
      mesh_.nodes_declared = true;
      mesh_.nodes.assign(mesh_.node_count, vec3d{NAN, NAN, NAN});
      return close_section(index);
    }
    if (!mesh_.nodes_declared) in_.fail("nodes before their count is declared (section 10, zone 0)");
    const Range r = zone_range(h, mesh_.node_count, "nodes");
    in_.expect('(', "opening the node coordinates");
    for (uint64_t n = r.first - 1; n < r.last; ++n) mesh_.nodes[n] = node(index);
    end_values(index);
  }
  vec3d node(int index) {
    vec3d p;
    for (int k = 0; k < 3; ++k) {
      if (!is_binary_index(index))
        p[k] = in_.real("a node coordinate");
      else if (is_double_index(index))
        p[k] = in_.binary<double>("the node coordinates");
      else
        p[k] = in_.binary<float>("the node coordinates");
    }
    return p;
  }

  void cells(int index) {
    const std::vector<uint64_t> h = header_numbers(in_, 16);
    if (h.size() < 4) in_.fail("a cell section header of fewer than 4 numbers");
    if (h[0] == 0) {
      mesh_.cell_count = declared_count(h[2], 1, "cells");
      mesh_.cells_declared = true;
      mesh_.cell_types.assign(mesh_.cell_count, 0);
      return close_section(index);
    }
    if (!mesh_.cells_declared) in_.fail("cells before their count is declared (section 12, zone 0)");
    if (h.size() < 5) in_.fail("a cell zone's header without its element type");
    const Range r = zone_range(h, mesh_.cell_count, "cells");
    mesh_.cell_zones.push_back({h[0], r});
    const uint64_t type = h[4];
    if (type != kMixed) {
      for (uint64_t c = r.first - 1; c < r.last; ++c) set_cell_type(c, type);
      return close_section(index);
    }
    in_.expect('(', "opening the cells' element types");
    for (uint64_t c = r.first - 1; c < r.last; ++c)
      set_cell_type(c, is_binary_index(index) ? uint64_t(in_.binary<uint32_t>("the element types"))
                                              : in_.number(16, "an element type"));
    end_values(index);
  }
  void set_cell_type(uint64_t cell, uint64_t type) {
    if (type == kTriangle || type == kQuad)
      in_.fail(std::string("a 2D cell (") + element_name(int(type)) + "): only 3D cases are read");
    if (type == kMixed || type > kPolyhedron)
      in_.fail("cell " + std::to_string(cell + 1) + " of unknown element type " + std::to_string(type));
    if (mesh_.cell_types[cell] != 0) in_.fail("cell " + std::to_string(cell + 1) + " is in two cell zones");
    mesh_.cell_types[cell] = uint8_t(type);
  }

  void faces(int index) {
    const std::vector<uint64_t> h = header_numbers(in_, 16);
    if (h.size() < 4) in_.fail("a face section header of fewer than 4 numbers");
    if (h[0] == 0) {
      mesh_.face_count = declared_count(h[2], 1, "faces");
      reserve_faces(std::min(mesh_.face_count, in_.size() / kLeastFaceBytes));
      return close_section(index);
    }
    if (!mesh_.nodes_declared || !mesh_.cells_declared) in_.fail("faces before the node and cell counts are declared");
    if (h.size() < 5) in_.fail("a face zone's header without its face type");
    const Range r = zone_range(h, mesh_.face_count, "faces");
    const uint64_t type = h[4];
    if (type == 2) in_.fail("line faces: only 3D cases are read");
    if (type != 0 && type != 3 && type != 4 && type != 5) in_.fail("unknown face type " + std::to_string(type));
    in_.expect('(', "opening the faces");
    in_.require_fits(r.count(), is_binary_index(index) ? 20 : 10, "faces");
    if (is_binary_index(index))
      binary_faces(type, r);
    else
      for (uint64_t f = r.first; f <= r.last; ++f) text_face(type, f);
    end_values(index);
  }
  // Room for the declared faces at once: grown by doubling, the face arrays were held at up to
  // twice their size, beside their last copy (massif of a 1M-cell case: 168 MB of the read's 321
  // MB peak). A face row takes kLeastFaceBytes of the file at least, so that a count the file
  // cannot hold reserves no more than the file could fill; quads are the common face (faces of
  // more vertices grow the list as before).
  static constexpr uint64_t kLeastFaceBytes = 10;
  void reserve_faces(uint64_t faces) {
    mesh_.faces.reserve(faces);
    mesh_.face_offsets.reserve(faces + 1);
    mesh_.face_vertices.reserve(4 * faces);
  }
  // A face's row: (for mixed and polygonal zones) its node count, its nodes, c0, c1.
  void text_face(uint64_t type, uint64_t id) {
    const uint64_t nodes = (type == 0 || type == 5) ? in_.number(16, "a face's node count") : type;
    check_node_count(id, nodes);
    in_.require_fits(nodes, 2, "face nodes");
    for (uint64_t k = 0; k < nodes; ++k) add_face_node(id, in_.number(16, "a face's node"));
    add_face_cells(id, {in_.number(16, "a face's c0 cell"), in_.number(16, "a face's c1 cell")});
  }
  // The rows of a binary zone, 32-bit values: each row taken as one block (one bounds check a
  // row, not one a value: the faces are most of a case file's bytes).
  void binary_faces(uint64_t type, const Range& r) {
    const auto u32 = [](const char* p) { return uint64_t(load_value<uint32_t>(p, false)); };
    for (uint64_t id = r.first; id <= r.last; ++id) {
      const uint64_t nodes = (type == 0 || type == 5) ? u32(in_.take(4, "a face's node count")) : type;
      check_node_count(id, nodes);
      const char* row = in_.take(4 * (nodes + 2), "a face's nodes and cells");
      for (uint64_t k = 0; k < nodes; ++k) add_face_node(id, u32(row + 4 * k));
      add_face_cells(id, {u32(row + 4 * nodes), u32(row + 4 * nodes + 4)});
    }
  }
  void check_node_count(uint64_t id, uint64_t nodes) {
    if (nodes < 3) in_.fail("face " + std::to_string(id) + " of " + std::to_string(nodes) + " nodes");
  }
  void add_face_node(uint64_t id, uint64_t n) {
    if (n < 1 || n > mesh_.node_count)
      in_.fail("face " + std::to_string(id) + ": node " + std::to_string(n) + " out of range 1.." +
               std::to_string(mesh_.node_count));
    mesh_.face_vertices.push_back(saturated_face_index(int64_t(n - 1)));  // past 32 bits: refused by the split
  }
  void add_face_cells(uint64_t id, const FaceCells& f) {
    mesh_.face_offsets.push_back(mesh_.face_vertices.size());
    if (f.first > mesh_.cell_count || f.second > mesh_.cell_count || (f.first == 0 && f.second == 0))
      in_.fail("face " + std::to_string(id) + ": cells " + std::to_string(f.first) + ", " + std::to_string(f.second) +
               " out of range 1.." + std::to_string(mesh_.cell_count));
    if (f.first == f.second)
      in_.fail("face " + std::to_string(id) + " has cell " + std::to_string(f.first) + " on both sides");
    mesh_.faces.push_back(f);
  }

  // "(39 (ID TYPE NAME ...) ...)" and "(45 (ID TYPE NAME) ...)". The format's description does not
  // say in which base these ids are written; Fluent's files read as decimal ones (zone 10 and up
  // are "a" and up in the mesh sections' hexadecimal headers but "10" here).
  void zone_name(int index) {
    in_.expect('(', "opening a zone's name");
    const uint64_t id = in_.number(10, "a zone id");
    in_.word("a zone type");
    mesh_.zone_names[id] = in_.word("a zone name");
    in_.skip_list();
    skip(index % 1000);  // the rest of the section: its settings
  }

  // A section with values: its values' ')' (binary: with its end line), then its own ')'.
  void end_values(int index) {
    if (is_binary_index(index)) return in_.end_binary_section(index);
    in_.expect(')', "closing the values");
    in_.expect(')', "closing the section");
  }
  void close_section(int index) {
    if (is_binary_index(index)) in_.fail("a declaration (zone 0) in binary section " + std::to_string(index));
    in_.expect(')', "closing the section");
  }

  // Every node has coordinates and every cell a zone, and there are faces enough for every cell
  // to have four (which bounds what a data file's values may make us allocate).
  void check_complete() {
    if (!mesh_.nodes_declared || !mesh_.cells_declared || mesh_.faces.empty())
      input_error(in_.file(), "no mesh: a case file declares its nodes, cells and faces (sections 10, 12, 13)");
    if (mesh_.faces.size() * 2 < mesh_.cell_count * 4)
      input_error(in_.file(), std::to_string(mesh_.cell_count) + " cells but only " +
                                  std::to_string(mesh_.faces.size()) + " faces");
    for (uint64_t n = 0; n < mesh_.node_count; ++n)
      if (std::isnan(mesh_.nodes[n][0]))
        input_error(in_.file(), "node " + std::to_string(n + 1) + " has no coordinates (in no node zone)");
    for (uint64_t c = 0; c < mesh_.cell_count; ++c)
      if (mesh_.cell_types[c] == 0) input_error(in_.file(), "cell " + std::to_string(c + 1) + " is in no cell zone");
  }

  Cursor in_;
  CaseMesh mesh_;
};

// The case's nodes move here: the split keeps them, and the data files need the cells alone.
MeshData unsplit_mesh(CaseMesh& m, uint64_t cells) {
  MeshData mesh;
  mesh.points = std::move(m.nodes);
  mesh.cell_types.assign(cells, kVtkPolyhedron);
  mesh.cell_offsets.assign(cells + 1, 0);  // a polyhedron's vertices are its faces'
  return mesh;
}

// The cell zones named (by name, or id where a zone has no name), in a mask over the case's
// zones; every zone where none is named. InputError naming `file` for a name the case lacks.
std::vector<char> chosen_zones(const CaseMesh& m, const std::vector<std::string>& names, const std::string& file) {
  std::vector<char> chosen(m.cell_zones.size(), names.empty());
  for (const std::string& name : names) {
    size_t z = 0;
    while (z < m.cell_zones.size() && zone_name(m, z) != name) ++z;
    if (z == m.cell_zones.size()) {
      std::string zones;
      for (size_t k = 0; k < m.cell_zones.size(); ++k) zones += (k ? ", " : "") + zone_name(m, k);
      input_error(file, "no cell zone '" + name + "' in this case (its cell zones: " + zones + ")");
    }
    chosen[z] = 1;
  }
  return chosen;
}

// The mesh of the chosen zones' cells alone: their faces (a face between a chosen and another
// cell is on the boundary), the nodes of those faces renumbered in order, the cells renumbered in
// order; returns the cells kept (0-based, of the case's numbering), whose values the data files
// give among the others'.
std::vector<uint64_t> keep_zones(CaseMesh& m, const std::vector<char>& chosen) {
  std::vector<uint64_t> kept, new_cell(m.cell_count + 1, 0);  // by 1-based cell; 0: not kept
  for (size_t z = 0; z < m.cell_zones.size(); ++z)
    if (chosen[z])
      for (uint64_t c = m.cell_zones[z].cells.first; c <= m.cell_zones[z].cells.last; ++c) new_cell[c] = 1;
  for (uint64_t c = 1; c <= m.cell_count; ++c)
    if (new_cell[c]) {
      kept.push_back(c - 1);
      new_cell[c] = kept.size();
    }
  constexpr uint64_t kUnused = ~uint64_t(0);
  std::vector<uint64_t> new_node(m.nodes.size(), kUnused);
  std::vector<uint64_t> offsets{0};
  std::vector<FaceIndex> vertices;
  std::vector<FaceCells> faces;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const FaceCells sides{new_cell[m.faces[f].first], new_cell[m.faces[f].second]};
    if (sides.first == 0 && sides.second == 0) continue;
    faces.push_back(sides);
    for (uint64_t k = m.face_offsets[f]; k < m.face_offsets[f + 1]; ++k) vertices.push_back(m.face_vertices[k]);
    offsets.push_back(vertices.size());
  }
  std::vector<vec3d> nodes;
  for (FaceIndex& v : vertices) {
    if (new_node[v] == kUnused) {
      new_node[v] = nodes.size();
      nodes.push_back(m.nodes[v]);
    }
    v = FaceIndex(new_node[v]);  // a kept node's new number: below the case's node count, as v is
  }
  std::vector<uint8_t> types;
  for (uint64_t c : kept) types.push_back(m.cell_types[c]);
  m.nodes = std::move(nodes);
  m.faces = std::move(faces);
  m.face_offsets = std::move(offsets);
  m.face_vertices = std::move(vertices);
  m.cell_types = std::move(types);
  return kept;
}

// The kept cells' values of each array (all where `kept` is empty).
void keep_cells(std::vector<MeshArray>& arrays, const std::vector<uint64_t>& kept) {
  if (kept.empty()) return;
  for (MeshArray& a : arrays) {
    const auto n = uint64_t(a.components);
    std::vector<double> values;
    values.reserve(kept.size() * n);
    for (uint64_t c : kept)
      values.insert(values.end(), a.values.begin() + int64_t(c * n), a.values.begin() + int64_t((c + 1) * n));
    a.values = std::move(values);
  }
}

// Fluent's variable (SV_) ids of the fields solvers write most, as they are called here.
std::string variable_name(uint64_t id) {
  static const std::map<uint64_t, const char*> kNames = {{1, "pressure"},
                                                         {2, "momentum"},
                                                         {3, "temperature"},
                                                         {4, "enthalpy"},
                                                         {5, "k"},
                                                         {6, "epsilon"},
                                                         {7, "species"},
                                                         {59, "mach"},
                                                         {63, "omega"},
                                                         {101, "density"},
                                                         {102, "viscosity_laminar"},
                                                         {103, "viscosity_turbulent"},
                                                         {104, "cp"},
                                                         {105, "thermal_conductivity"},
                                                         {111, "x_velocity"},
                                                         {112, "y_velocity"},
                                                         {113, "z_velocity"},
                                                         {150, "vof"},
                                                         {192, "total_pressure"},
                                                         {193, "total_temperature"},
                                                         {500, "nut"}};
  const auto it = kNames.find(id);
  return it == kNames.end() ? "SV_" + std::to_string(id) : it->second;
}
constexpr uint64_t kSvU = 111, kSvV = 112, kSvW = 113;

// One variable's values over the cells, as the data file's sections fill them.
struct Variable {
  int components = 0;
  std::vector<double> values;               // NaN ("no data") where nothing was read
  std::vector<bool> zones_read, zones_met;  // per cell zone: every cell read, some cell read
};

class DataReader {
 public:
  DataReader(const fs::path& file, const CaseMesh& mesh) : in_(read_file_inflating(file), file.string()), mesh_(mesh) {}

  // The cell values by variable id. A variable without values on a cell zone (as a solid's
  // velocity) has NaN, no data, there ("NAME in ZONE" goes to `no_data`); one with values on
  // part of a zone's cells is left out (its name goes to `left_out`).
  // Only the zones `chosen` count (those read; a variable on none of them is left out too).
  std::map<uint64_t, Variable> read(const std::vector<char>& chosen, std::vector<std::string>& left_out,
                                    std::vector<std::string>& no_data) {
    while (!in_.at_end()) section();
    if (variables_.empty())
      input_error(in_.file(), "no cell values (no data section 300, 2300 or 3300 on a cell zone)");
    for (auto it = variables_.begin(); it != variables_.end();) {
      const Variable& v = it->second;
      bool partly = false, anywhere = false;
      for (size_t z = 0; z < v.zones_read.size(); ++z) {
        partly = partly || (chosen[z] && v.zones_met[z] && !v.zones_read[z]);
        anywhere = anywhere || (chosen[z] && v.zones_met[z]);
      }
      if (partly || !anywhere) {
        left_out.push_back(variable_name(it->first));
        it = variables_.erase(it);
        continue;
      }
      for (size_t z = 0; z < v.zones_read.size(); ++z)
        if (chosen[z] && !v.zones_met[z]) no_data.push_back(variable_name(it->first) + " in " + zone_name(mesh_, z));
      ++it;
    }
    return std::move(variables_);
  }

 private:
  void section() {
    in_.expect('(', "opening a section");
    const int index = int(in_.number(10, "a section index"));
    if (index == 300 || index == 2300 || index == 3300)
      values(index);
    else if (is_binary_index(index))
      in_.skip_unknown_binary_section(index);
    else
      in_.skip_list();
  }

  // "(300 (SV ZONE SIZE TIME-LEVELS PHASES FIRST LAST)(values))": the header in decimal, as VTK's
  // reader takes it (the format's description calls every header number hexadecimal; Fluent's
  // data files hold decimal ones); SIZE values per cell or face of FIRST..LAST.
  void values(int index) {
    const std::vector<uint64_t> h = header_numbers(in_, 10);
    if (h.size() != 7) in_.fail("a data section header of " + std::to_string(h.size()) + " numbers, not 7");
    const uint64_t sv = h[0], zone = h[1], size = h[2];
    const Range r{h[5], h[6]};
    if (size < 1 || size > 64 || r.first < 1 || r.last < r.first)
      in_.fail("data section of variable " + std::to_string(sv) + ": size " + std::to_string(size) + ", ids " +
               std::to_string(r.first) + ".." + std::to_string(r.last));
    const uint64_t bytes = is_binary_index(index) ? (is_double_index(index) ? 8 : 4) : 2;
    in_.require_fits(r.count() * size, bytes, "data values");
    in_.expect('(', "opening the values");
    const auto z =
        std::find_if(mesh_.cell_zones.begin(), mesh_.cell_zones.end(), [&](const CellZone& c) { return c.id == zone; });
    if (z == mesh_.cell_zones.end())
      skip_values(index, r.count() * size);  // a face zone's
    else
      read_cell_values(index, sv, int(size), *z, size_t(z - mesh_.cell_zones.begin()), r);
    if (is_binary_index(index)) return in_.end_binary_section(index);
    in_.expect(')', "closing the values");
    in_.expect(')', "closing the section");
  }
  void skip_values(int index, uint64_t count) {
    if (!is_binary_index(index))
      for (uint64_t k = 0; k < count; ++k) in_.real("a value");
    else
      in_.skip_bytes(count * (is_double_index(index) ? 8 : 4), "the values");
  }
  void read_cell_values(int index, uint64_t sv, int size, const CellZone& zone, size_t zone_index, const Range& r) {
    if (r.first < zone.cells.first || r.last > zone.cells.last)
      in_.fail("values of cells " + std::to_string(r.first) + ".." + std::to_string(r.last) + " in cell zone " +
               std::to_string(zone.id) + " of cells " + std::to_string(zone.cells.first) + ".." +
               std::to_string(zone.cells.last));
    Variable& v = variables_[sv];
    if (v.components == 0) {
      v.components = size;
      v.values.assign(mesh_.cell_count * uint64_t(size), NAN);
      v.zones_read.assign(mesh_.cell_zones.size(), false);
      v.zones_met.assign(mesh_.cell_zones.size(), false);
    }
    if (v.components != size)
      in_.fail("variable " + std::to_string(sv) + " of both " + std::to_string(v.components) + " and " +
               std::to_string(size) + " components");
    double* out = v.values.data() + (r.first - 1) * uint64_t(size);
    const uint64_t n = r.count() * uint64_t(size);
    if (!is_binary_index(index))
      for (uint64_t k = 0; k < n; ++k) out[k] = in_.real("a value");
    else if (is_double_index(index))  // taken as one block: one bounds check, not one a value
      load_values<double>(in_.take(n * 8, "the values"), n, false, out);
    else
      load_values<float>(in_.take(n * 4, "the values"), n, false, out);
    v.zones_met[zone_index] = true;
    if (r.first == zone.cells.first && r.last == zone.cells.last) v.zones_read[zone_index] = true;
  }

  Cursor in_;
  const CaseMesh& mesh_;
  std::map<uint64_t, Variable> variables_;
};

bool is_scalar(const std::map<uint64_t, Variable>& variables, uint64_t id) {
  const auto it = variables.find(id);
  return it != variables.end() && it->second.components == 1;
}

// The cell arrays of a data file's variables: SV_U, SV_V, SV_W (scalars all three) as one
// vector "velocity", as ParaView users know it; the others by variable_name().
std::vector<MeshArray> cell_arrays(std::map<uint64_t, Variable> variables) {
  std::vector<MeshArray> arrays;
  if (is_scalar(variables, kSvU) && is_scalar(variables, kSvV) && is_scalar(variables, kSvW)) {
    const std::vector<double>&u = variables[kSvU].values, &v = variables[kSvV].values, &w = variables[kSvW].values;
    MeshArray velocity{"velocity", 3, {}};
    velocity.values.reserve(u.size() * 3);
    for (size_t c = 0; c < u.size(); ++c) velocity.values.insert(velocity.values.end(), {u[c], v[c], w[c]});
    arrays.push_back(std::move(velocity));
    for (uint64_t id : {kSvU, kSvV, kSvW}) variables.erase(id);
  }
  for (auto& [id, v] : variables) arrays.push_back({variable_name(id), v.components, std::move(v.values)});
  return arrays;
}

// The "(flow-time T)" among a data file's settings (section 37), looked for in its first MiB
// (the settings come before the values); VTK's reader reads no time.
std::optional<double> flow_time(const fs::path& file) {
  const std::string text = read_file_inflating(file, 1 << 20);
  const size_t at = text.find("(flow-time ");
  if (at == std::string::npos) return std::nullopt;
  char* end = nullptr;
  const double t = std::strtod(text.c_str() + at + std::strlen("(flow-time "), &end);
  if (end == text.c_str() + at + std::strlen("(flow-time ") || !std::isfinite(t)) return std::nullopt;
  return t;
}

std::string case_stem(const fs::path& case_file) {
  std::string name = case_file.filename().string();
  name.erase(name.size() - (name_ends_with(case_file, ".gz") ? 7 : 4));  // ".cas.gz" or ".cas"
  return name;
}

}  // namespace

bool is_fluent_case_file(const fs::path& file) {
  return name_ends_with(file, ".cas") || name_ends_with(file, ".cas.gz");
}
bool is_fluent_data_file(const fs::path& file) {
  return name_ends_with(file, ".dat") || name_ends_with(file, ".dat.gz");
}

struct FluentFile::Impl {
  fs::path case_file;
  std::vector<fs::path> data_files;
  CaseMesh mesh;                        // its zones and cell count as declared, for the data files
  std::vector<char> chosen;             // the cell zones read, by index
  std::vector<uint64_t> kept;           // the cells read (empty: every cell)
  PolyhedronFaces faces;                // each cell's, from the mesh's faces; released once split
  std::optional<FixedMeshSplit> split;  // made at the first step read
  std::vector<double> times;
  std::vector<std::string> left_out, no_data;  // of the last step read

  void find_data_file() {
    for (const char* ext : {".dat", ".dat.gz"}) {
      const fs::path candidate = case_file.parent_path() / (case_stem(case_file) + ext);
      if (fs::exists(candidate)) return data_files.push_back(candidate);
    }
  }
  void read_times() {
    std::vector<std::optional<double>> found;
    for (const fs::path& f : data_files) found.push_back(flow_time(f));
    const bool all = !found.empty() && std::all_of(found.begin(), found.end(), [](auto& t) { return t.has_value(); });
    for (size_t s = 0; s < std::max<size_t>(data_files.size(), 1); ++s) times.push_back(all ? *found[s] : double(s));
  }
};

FluentFile::FluentFile(const fs::path& case_file, std::vector<fs::path> data_files,
                       const std::vector<std::string>& zones)
    : impl_(std::make_unique<Impl>()) {
  impl_->case_file = case_file;
  impl_->data_files = std::move(data_files);
  impl_->mesh = CaseReader(case_file).read();
  CaseMesh& m = impl_->mesh;
  impl_->chosen = chosen_zones(m, zones, case_file.string());
  if (std::find(impl_->chosen.begin(), impl_->chosen.end(), 0) != impl_->chosen.end())
    impl_->kept = keep_zones(m, impl_->chosen);
  impl_->faces = polyhedra_from_face_cells(std::move(m.face_offsets), std::move(m.face_vertices), m.faces,
                                           m.cell_types.size(), case_file.string());
  release(m.faces);  // each cell has its faces now
  if (impl_->data_files.empty()) impl_->find_data_file();
  impl_->read_times();
}
FluentFile::~FluentFile() = default;

size_t FluentFile::step_count() const { return impl_->times.size(); }
double FluentFile::step_time(size_t step) const { return impl_->times.at(step); }
fs::path FluentFile::step_file(size_t step) const {
  return impl_->data_files.empty() ? impl_->case_file : impl_->data_files.at(step);
}

FixedMeshSplit& FluentFile::split_mesh() {
  if (!impl_->split) {
    impl_->split.emplace(unsplit_mesh(impl_->mesh, impl_->mesh.cell_types.size()), impl_->faces,
                         impl_->case_file.string());
    impl_->faces = {};
  }
  return *impl_->split;
}

std::vector<MeshArray> FluentFile::read_cell_data(size_t step) {
  input_check(step < step_count(), impl_->case_file.string(), "no time step " + std::to_string(step));
  std::vector<MeshArray> cell_data;
  if (!impl_->data_files.empty()) {
    impl_->left_out.clear();
    impl_->no_data.clear();
    cell_data = cell_arrays(
        DataReader(impl_->data_files[step], impl_->mesh).read(impl_->chosen, impl_->left_out, impl_->no_data));
    keep_cells(cell_data, impl_->kept);
  }
  split_mesh().split_cell_data(cell_data, step_file(step).string());
  return cell_data;
}

MeshData FluentFile::read_step(size_t step) {
  std::vector<MeshArray> cell_data = read_cell_data(step);
  return split_mesh().mesh_with(std::move(cell_data), impl_->case_file.string());
}

MeshData FluentFile::take_step(size_t step) {
  std::vector<MeshArray> cell_data = read_cell_data(step);
  return split_mesh().take_mesh_with(std::move(cell_data), impl_->case_file.string());
}

std::string FluentFile::summary() const {
  const CaseMesh& m = impl_->mesh;
  std::string s = std::to_string(m.cell_zones.size()) + (m.cell_zones.size() == 1 ? " cell zone (" : " cell zones (");
  for (size_t z = 0; z < m.cell_zones.size(); ++z) s += (z ? ", " : "") + zone_name(m, z);
  if (!impl_->kept.empty()) {
    s += "; read:";
    for (size_t z = 0; z < m.cell_zones.size(); ++z)
      if (impl_->chosen[z]) s += " " + zone_name(m, z);
  }
  std::map<std::string, uint64_t> counts;
  for (uint8_t t : m.cell_types) ++counts[element_name(t)];
  const char* sep = "): ";
  for (const auto& [type, n] : counts) {
    s += sep + type + " x " + std::to_string(n);
    sep = ", ";
  }
  if (!impl_->no_data.empty()) {
    s += "; no data (NaN) for";
    for (const std::string& name : impl_->no_data) s += (name == impl_->no_data.front() ? " " : ", ") + name;
  }
  if (!impl_->left_out.empty()) {
    s += "; left out (on part of a cell zone's cells, or on no zone read):";
    for (const std::string& name : impl_->left_out) s += " " + name;
  }
  return s;
}

}  // namespace vs
