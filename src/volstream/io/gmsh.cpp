#include "volstream/io/gmsh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/parse_cursor.h"
#include "volstream/umesh/mesh_pieces.h"
#include "volstream/umesh/quadratic.h"

namespace vs {
namespace fs = std::filesystem;

namespace {

// A Gmsh element type's node count and dimension (the manual's list of types up to third order,
// and its tetrahedra and hexahedra of higher order), so that elements not read can be skipped.
struct GmshType {
  int type, nodes, dim;
};
constexpr GmshType kGmshTypes[] = {
    {1, 2, 1},   {2, 3, 2},   {3, 4, 2},   {4, 4, 3},   {5, 8, 3},   {6, 6, 3},   {7, 5, 3},   {8, 3, 1},   {9, 6, 2},
    {10, 9, 2},  {11, 10, 3}, {12, 27, 3}, {13, 18, 3}, {14, 14, 3}, {15, 1, 0},  {16, 8, 2},  {17, 20, 3}, {18, 15, 3},
    {19, 13, 3}, {20, 9, 2},  {21, 10, 2}, {22, 12, 2}, {23, 15, 2}, {24, 15, 2}, {25, 21, 2}, {26, 4, 1},  {27, 5, 1},
    {28, 6, 1},  {29, 20, 3}, {30, 35, 3}, {31, 56, 3}, {92, 64, 3}, {93, 125, 3}};

std::optional<GmshType> gmsh_type(int64_t type) {
  for (const GmshType& t : kGmshTypes)
    if (t.type == type) return t;
  return std::nullopt;
}

// A volume element read, as VTK's cell: for each VTK node, the Gmsh node (0-based) that is it.
// Derived from the node-ordering figures of Gmsh's manual and VTK's cell documentation:
// - tet10: Gmsh's last two edges are (3,2), (3,1); VTK's (1,3), (2,3).
// - prisms: Gmsh's first triangle (0,1,2) turns towards the second, VTK's away from it, so the
//   triangles' second and third nodes change places (as io/solver_files.h's Exodus wedge).
// - hex20: Gmsh's edges are (0,1) (0,3) (0,4) (1,2) (1,5) (2,3) (2,6) (3,7) (4,5) (4,7) (5,6)
//   (6,7); VTK's the bottom's four in turn, the top's, then the vertical ones.
// - hex27: then Gmsh's face centres -z, -y, -x, +x, +y, +z; VTK's -x, +x, -y, +y, -z, +z; both
//   end with the body's centre.
// - prism15: Gmsh's edges (0,1) (0,2) (0,3) (1,2) (1,4) (2,5) (3,4) (3,5) (4,5); VTK's the
//   bottom triangle's in turn, the top's, the vertical ones (of the turned prism).
// - prism18: then Gmsh's quad-face centres (0,1,4,3) (0,2,5,3) (1,2,5,4); VTK's (0,1,4,3)
//   (1,2,5,4) (2,0,3,5) of the turned prism.
// - pyramid13: Gmsh's edges (0,1) (0,3) (0,4) (1,2) (1,4) (2,3) (2,4) (3,4); VTK's the base's
//   four in turn, then the four to the apex.
struct VolumeKind {
  int gmsh_type;
  const char* name;
  uint8_t vtk_type;
  std::vector<int> vtk_from_gmsh;  // empty: the same order
};

const std::vector<VolumeKind>& volume_kinds() {
  static const std::vector<VolumeKind> kinds = {
      {4, "tet4", 10, {}},
      {5, "hex8", 12, {}},
      {6, "prism6", 13, {0, 2, 1, 3, 5, 4}},
      {7, "pyramid5", 14, {}},
      {11, "tet10", uint8_t(QuadraticCell::tet10), {0, 1, 2, 3, 4, 5, 6, 7, 9, 8}},
      {17, "hex20", uint8_t(QuadraticCell::hex20), {0,  1, 2,  3,  4,  5,  6,  7,  8,  11,
                                                    13, 9, 16, 18, 19, 17, 10, 12, 14, 15}},
      {12, "hex27", uint8_t(QuadraticCell::hex27), {0,  1,  2,  3,  4,  5,  6,  7,  8,  11, 13, 9,  16, 18,
                                                    19, 17, 10, 12, 14, 15, 22, 23, 21, 24, 20, 25, 26}},
      {18, "prism15", uint8_t(QuadraticCell::wedge15), {0, 2, 1, 3, 5, 4, 7, 9, 6, 13, 14, 12, 8, 11, 10}},
      {13, "prism18", uint8_t(QuadraticCell::wedge18), {0, 2, 1, 3, 5, 4, 7, 9, 6, 13, 14, 12, 8, 11, 10, 16, 17, 15}},
      {19, "pyramid13", uint8_t(QuadraticCell::pyramid13), {0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12}},
  };
  return kinds;
}

const VolumeKind* volume_kind(int64_t type) {
  for (const VolumeKind& k : volume_kinds())
    if (k.gmsh_type == type) return &k;
  return nullptr;
}

// File tags (node or element numbers: any positive integers, in any order, possibly sparse) to
// 0-based indices: a table when the tags are dense enough, else a hash map, so a huge tag in a
// small file costs no memory.
class TagIndex {
 public:
  // Tag tags[i] is index i, and each of `aliases` (tag, index) names an index too (an element's
  // other copies). False if a tag is repeated.
  bool build(const std::vector<uint64_t>& tags, const std::vector<std::pair<uint64_t, uint64_t>>& aliases = {}) {
    uint64_t max = 0;
    for (uint64_t t : tags) max = std::max(max, t);
    for (const auto& a : aliases) max = std::max(max, a.first);
    const uint64_t n = tags.size() + aliases.size();
    dense_ = max <= 2 * n + 1024;
    if (dense_) table_.assign(max + 1, kNone);
    for (size_t i = 0; i < tags.size(); ++i)
      if (!add(tags[i], i)) return false;
    for (const auto& [tag, index] : aliases)
      if (!add(tag, index)) return false;
    return true;
  }
  bool add(uint64_t tag, uint64_t index) {
    if (!dense_) return map_.emplace(tag, index).second;
    if (table_[tag] != kNone) return false;
    table_[tag] = index;
    return true;
  }
  std::optional<uint64_t> find(int64_t tag) const {
    if (tag < 0) return std::nullopt;
    if (dense_) {
      if (uint64_t(tag) >= table_.size() || table_[size_t(tag)] == kNone) return std::nullopt;
      return table_[size_t(tag)];
    }
    const auto it = map_.find(uint64_t(tag));
    if (it == map_.end()) return std::nullopt;
    return it->second;
  }

 private:
  static constexpr uint64_t kNone = ~uint64_t(0);
  bool dense_ = true;
  std::vector<uint64_t> table_;
  std::unordered_map<uint64_t, uint64_t> map_;
};

// One view's values at one time step: per node (or kept element), `components` each; `given`
// marks those the file gave (a view may come in several partitions).
struct ViewStep {
  double time = 0;
  std::vector<double> values;
  std::vector<uint8_t> given;
};

struct View {
  std::string name;
  bool cells = false;  // $ElementData, else $NodeData
  int components = 1;
  std::map<int64_t, ViewStep> steps;  // by the file's time-step index
};

// What a file holds, in the file's node order; elements in VTK's node order, not yet split.
struct GmshContents {
  std::string format;  // "MSH 4.1 binary"
  std::vector<vec3d> points;
  TagIndex nodes;
  MeshData cells;  // connectivity, types and offsets only
  std::vector<uint64_t> node_tags, element_tags;
  std::vector<std::pair<uint64_t, uint64_t>> element_copies;  // 2.2: (tag, element) of a copy read as its first
  TagIndex elements;
  std::map<int64_t, std::string> groups_read;        // --region: the physical groups of volumes read, and their names
  std::map<std::string_view, uint64_t> kind_counts;  // "tet4" -> elements read (no string made per element)
  std::vector<View> views;
  std::vector<std::string> left_out;  // for summary()
};

class MshParser {
 public:
  // `groups`: the physical groups of volumes to read, by name or number (empty: every element).
  MshParser(const fs::path& file, std::vector<std::string> groups) : in_(file), wanted_(std::move(groups)) {
    matched_.assign(wanted_.size(), false);
  }
  GmshContents parse();

 private:
  void read_format();
  void read_section(std::string_view name);
  void skip_section(std::string_view name);
  void expect_end(std::string_view name);
  void start_binary();

  uint64_t count(const char* what);  // 4.1's size_t
  int64_t int_value(const char* what);
  double real_value(const char* what);
  uint64_t tag(const char* what) { return v41_ ? count(what) : positive_int(what); }
  uint64_t positive_int(const char* what);

  void read_nodes();
  void read_nodes_41();
  uint64_t ascii_count(const char* what);
  void finish_nodes();
  void read_elements();
  void read_element(int64_t type, uint64_t element_tag, std::vector<int64_t>& nodes, bool wanted = true);
  void keep_element(int64_t type, uint64_t element_tag, const std::vector<int64_t>& nodes);
  void read_elements_41();
  void read_elements_22(uint64_t total);
  void read_element_22(int64_t type, uint64_t element_tag, const std::vector<int64_t>& tags,
                       std::vector<int64_t>& nodes);
  void finish_elements();
  void keep_wanted_groups_22();
  void read_physical_names();
  void read_entities(bool partitioned);
  int64_t read_entity(int dim, bool partitioned, std::vector<int64_t>& groups);
  bool group_wanted(int64_t group);
  bool volume_wanted(int64_t entity);
  void check_groups_found() const;
  void note_entity_group(int64_t entity, int64_t group);
  std::optional<uint64_t> earlier_copy(size_t first, uint8_t vtk_type) const;
  uint64_t nodes_hash(size_t first, size_t end, uint8_t vtk_type) const;
  void index_element(uint64_t e);
  void place_in_index(uint64_t e);
  void read_view(bool cells);
  std::string string_tag();

  ParseCursor in_;
  bool binary_ = false, big_endian_ = false, v41_ = false;
  bool have_nodes_ = false, have_elements_ = false;
  std::map<int64_t, uint64_t> unread_volumes_;  // Gmsh type -> elements not read
  // --region: the groups asked for, which of them named a group, the file's names of volume
  // groups ($PhysicalNames), its volumes' groups (4.1 $Entities) and the groups seen (2.2).
  std::vector<std::string> wanted_;
  std::vector<bool> matched_;
  std::map<int64_t, std::string> group_names_;
  std::map<int64_t, std::vector<int64_t>> volume_groups_;
  std::set<int64_t> groups_seen_;
  bool have_entities_ = false;
  // 2.2 writes an element once for each physical group holding it, each copy under a number of
  // its own (and a view's values may be given for any copy): the copies after the first are read
  // as aliases of it. They can exist once an elementary volume comes under a second group; from
  // then on every element is looked up by its nodes.
  std::map<int64_t, int64_t> entity_group_;
  std::vector<int64_t> element_group_;                     // 2.2 with --region: each element's first group
  std::vector<std::pair<uint64_t, int64_t>> copy_groups_;  // and (element, group) of its copies
  bool copies_possible_ = false;
  // The elements by nodes_hash: open addressing, linear probing, element + 1 in a slot (0:
  // empty), a quarter to half full (16 to 32 bytes an element; a hash map's nodes take more).
  std::vector<uint64_t> element_index_;
  uint64_t indexed_ = 0;
  uint64_t view_tuples_ = 0;  // nodes and elements of every view step so far
  GmshContents out_;
};

uint64_t MshParser::count(const char* what) {
  if (binary_) return in_.binary<uint64_t>(big_endian_, what);
  const int64_t v = in_.integer(what);
  if (v < 0) in_.fail(std::string("negative ") + what + " " + std::to_string(v));
  return uint64_t(v);
}

int64_t MshParser::int_value(const char* what) {
  return binary_ ? in_.binary<int32_t>(big_endian_, what) : in_.integer(what);
}

double MshParser::real_value(const char* what) {
  return binary_ ? in_.binary<double>(big_endian_, what) : in_.real(what);
}

uint64_t MshParser::ascii_count(const char* what) {
  const int64_t v = in_.integer(what);
  if (v < 0) in_.fail(std::string("negative ") + what + " " + std::to_string(v));
  return uint64_t(v);
}

uint64_t MshParser::positive_int(const char* what) {
  const int64_t v = int_value(what);
  if (v < 0) in_.fail(std::string("negative ") + what + " " + std::to_string(v));
  return uint64_t(v);
}

// Binary data begins on the line after the ascii words before it.
void MshParser::start_binary() {
  if (!binary_) return;
  const std::string_view rest = in_.line();
  if (rest.find_first_not_of(" \t") != std::string_view::npos)
    in_.fail("binary data expected after a header line, found '" + std::string(rest.substr(0, 20)) + "'");
}

void MshParser::expect_end(std::string_view name) {
  const std::string end = "$End" + std::string(name.substr(1));
  const std::string_view w = in_.word(end.c_str());
  if (w != end) in_.fail("expected " + end + ", found '" + std::string(w.substr(0, 20)) + "'");
}

void MshParser::skip_section(std::string_view name) {
  const std::string end = "$End" + std::string(name.substr(1));
  if (!in_.skip_past(end)) in_.fail("truncated: no " + end + " after " + std::string(name));
}

// "$MeshFormat", "VERSION FILE-TYPE DATA-SIZE", in binary files the int 1 (for the byte order).
void MshParser::read_format() {
  if (in_.word("$MeshFormat") != "$MeshFormat") in_.fail("not a Gmsh MSH file (no $MeshFormat at its start)");
  const std::string version(in_.word("version"));
  if (version != "4.1" && version != "2.2")
    in_.fail("MSH version " + version.substr(0, 20) + " is not read (4.1 and 2.2 are; gmsh -format msh41 converts)");
  v41_ = version == "4.1";
  const int64_t file_type = in_.integer("file type");
  if (file_type != 0 && file_type != 1) in_.fail("file type " + std::to_string(file_type) + " (0 ascii, 1 binary)");
  binary_ = file_type == 1;
  const int64_t data_size = in_.integer("data size");
  if (data_size != 8) in_.fail("data size " + std::to_string(data_size) + " (8 is read)");
  if (binary_) {
    start_binary();
    const char* one = in_.take(4, "byte order mark");
    if (load_value<int32_t>(one, false) == 1)
      big_endian_ = false;
    else if (load_value<int32_t>(one, true) == 1)
      big_endian_ = true;
    else
      in_.fail("binary file without the int 1 after its header");
  }
  expect_end("$MeshFormat");
  out_.format = "MSH " + version + (binary_ ? " binary" : " ascii");
}

void MshParser::read_nodes() {
  if (have_nodes_) in_.fail("a second $Nodes section");
  if (v41_) {
    read_nodes_41();
  } else {
    // 2.2: the count in ascii, then "tag x y z" per node (binary: int tag, 3 doubles).
    const uint64_t n = ascii_count("node count");
    start_binary();
    in_.require_fits(n, binary_ ? 28 : 8, "$Nodes");
    out_.node_tags.reserve(n);
    out_.points.reserve(n);
    for (uint64_t i = 0; i < n; ++i) {
      out_.node_tags.push_back(positive_int("node tag"));
      vec3d p;
      p.x = real_value("x coordinate");
      p.y = real_value("y coordinate");
      p.z = real_value("z coordinate");
      out_.points.push_back(p);
    }
  }
  expect_end("$Nodes");
  finish_nodes();
}

// 4.1: "numEntityBlocks numNodes minNodeTag maxNodeTag", then per block "entityDim entityTag
// parametric numNodesInBlock", the block's tags, then its coordinates (x y z, and u, v, w up to
// the entity's dimension when parametric).
void MshParser::read_nodes_41() {
  const uint64_t blocks = count("node block count");
  const uint64_t total = count("node count");
  count("minimum node tag");
  count("maximum node tag");
  in_.require_fits(blocks, binary_ ? 20 : 8, "$Nodes entity blocks");
  in_.require_fits(total, binary_ ? 32 : 8, "$Nodes");
  out_.node_tags.reserve(total);
  out_.points.reserve(total);
  for (uint64_t b = 0; b < blocks; ++b) {
    const int64_t dim = int_value("entity dimension");
    int_value("entity tag");
    const int64_t parametric = int_value("parametric flag");
    const uint64_t n = count("nodes in block");
    if (dim < 0 || dim > 3 || (parametric != 0 && parametric != 1))
      in_.fail("$Nodes block " + std::to_string(b + 1) + ": entity dimension " + std::to_string(dim) + ", parametric " +
               std::to_string(parametric));
    if (n > total - out_.node_tags.size())
      in_.fail("$Nodes blocks hold more than the " + std::to_string(total) + " nodes its header gives");
    for (uint64_t i = 0; i < n; ++i) out_.node_tags.push_back(count("node tag"));
    const int64_t extra = parametric ? dim : 0;
    for (uint64_t i = 0; i < n; ++i) {
      vec3d p;
      p.x = real_value("x coordinate");
      p.y = real_value("y coordinate");
      p.z = real_value("z coordinate");
      for (int64_t k = 0; k < extra; ++k) real_value("parametric coordinate");
      out_.points.push_back(p);
    }
  }
  if (out_.node_tags.size() != total)
    in_.fail("$Nodes blocks hold " + std::to_string(out_.node_tags.size()) + " nodes, its header " +
             std::to_string(total));
}

void MshParser::finish_nodes() {
  if (!out_.nodes.build(out_.node_tags)) in_.fail("a node tag given twice in $Nodes");
  have_nodes_ = true;
}

void MshParser::read_elements() {
  if (!have_nodes_) in_.fail("$Elements before $Nodes");
  if (have_elements_) in_.fail("a second $Elements section");
  out_.cells.cell_offsets.push_back(0);
  if (v41_) {
    read_elements_41();
  } else {
    const uint64_t n = ascii_count("element count");
    start_binary();
    read_elements_22(n);
  }
  expect_end("$Elements");
  finish_elements();
}

// Element `element_tag` of `type`: its node tags read into `nodes`, then kept if it is a volume
// element read (and `wanted`: in a physical group asked for), counted if it is another volume
// element, else dropped.
void MshParser::read_element(int64_t type, uint64_t element_tag, std::vector<int64_t>& nodes, bool wanted) {
  const std::optional<GmshType> t = gmsh_type(type);
  if (!t) in_.fail("element " + std::to_string(element_tag) + ": unknown element type " + std::to_string(type));
  nodes.resize(size_t(t->nodes));
  for (int64_t& n : nodes) n = int64_t(tag("element node tag"));
  if (t->dim < 3 || !wanted) return;
  if (!volume_kind(type)) {
    ++unread_volumes_[type];
    return;
  }
  keep_element(type, element_tag, nodes);
}

void MshParser::keep_element(int64_t type, uint64_t element_tag, const std::vector<int64_t>& nodes) {
  const VolumeKind& kind = *volume_kind(type);
  MeshData& m = out_.cells;
  const size_t first = m.connectivity.size();
  for (size_t v = 0; v < nodes.size(); ++v) {
    const int64_t node = nodes[kind.vtk_from_gmsh.empty() ? v : size_t(kind.vtk_from_gmsh[v])];
    const std::optional<uint64_t> index = out_.nodes.find(node);
    if (!index)
      in_.fail("element " + std::to_string(element_tag) + " (" + kind.name + "): node tag " + std::to_string(node) +
               " is not in $Nodes");
    m.connectivity.push_back(*index);
  }
  if (copies_possible_) {
    if (const std::optional<uint64_t> e = earlier_copy(first, kind.vtk_type)) {
      m.connectivity.resize(first);
      out_.element_copies.push_back({element_tag, *e});
      return;
    }
  }
  m.cell_types.push_back(kind.vtk_type);
  m.cell_offsets.push_back(m.connectivity.size());
  out_.element_tags.push_back(element_tag);
  ++out_.kind_counts[kind.name];
  if (copies_possible_) index_element(m.cell_count() - 1);
}

// 4.1: "numEntityBlocks numElements minElementTag maxElementTag", then per block "entityDim
// entityTag elementType numElementsInBlock" and its elements, "elementTag nodeTag ...".
void MshParser::read_elements_41() {
  const uint64_t blocks = count("element block count");
  const uint64_t total = count("element count");
  count("minimum element tag");
  count("maximum element tag");
  in_.require_fits(blocks, binary_ ? 20 : 8, "$Elements entity blocks");
  in_.require_fits(total, binary_ ? 16 : 4, "$Elements");
  uint64_t seen = 0;
  std::vector<int64_t> nodes;
  for (uint64_t b = 0; b < blocks; ++b) {
    const int64_t dim = int_value("entity dimension");
    const int64_t entity = int_value("entity tag");
    const int64_t type = int_value("element type");
    const uint64_t n = count("elements in block");
    if (n > total - seen)
      in_.fail("$Elements blocks hold more than the " + std::to_string(total) + " elements its header gives");
    seen += n;
    const std::optional<GmshType> t = gmsh_type(type);
    if (!t && !binary_ && dim < 3) {
      // A type this reader does not know, on a surface or curve: one element a line, skipped.
      for (uint64_t e = 0; e <= n; ++e) in_.skip_line();
      continue;
    }
    if (t && dim != t->dim)
      in_.fail("$Elements block " + std::to_string(b + 1) + ": element type " + std::to_string(type) +
               " on an entity of dimension " + std::to_string(dim));
    if (t) in_.require_fits(n, uint64_t(t->nodes + 1) * (binary_ ? 8 : 2), "$Elements block");
    const bool wanted = dim < 3 || volume_wanted(entity);
    for (uint64_t e = 0; e < n; ++e) read_element(type, count("element tag"), nodes, wanted);
  }
  if (seen != total)
    in_.fail("$Elements blocks hold " + std::to_string(seen) + " elements, its header " + std::to_string(total));
}

// 2.2 ascii: per element "tag type numTags tags... nodes"; binary: blocks of one type, "type
// count numTags" (ints), then per element its tag, tags and nodes (ints).
void MshParser::read_elements_22(uint64_t total) {
  in_.require_fits(total, binary_ ? 8 : 4, "$Elements");
  std::vector<int64_t> nodes, tags;
  for (uint64_t seen = 0; seen < total;) {
    if (binary_) {
      const int64_t type = int_value("element type");
      const int64_t n = int_value("element count");
      const int64_t tag_count = int_value("tag count");
      const std::optional<GmshType> t = gmsh_type(type);
      if (!t) in_.fail("unknown element type " + std::to_string(type));
      if (n < 0 || uint64_t(n) > total - seen || tag_count < 0 || tag_count > 1024)
        in_.fail("an element block of " + std::to_string(n) + " elements with " + std::to_string(tag_count) + " tags");
      in_.require_fits(uint64_t(n), 4 * uint64_t(1 + tag_count + t->nodes), "$Elements block");
      tags.resize(size_t(tag_count));
      for (int64_t e = 0; e < n; ++e) {
        const uint64_t element_tag = positive_int("element tag");
        for (int64_t& k : tags) k = int_value("element tag");
        read_element_22(type, element_tag, tags, nodes);
      }
      seen += uint64_t(n);
    } else {
      const uint64_t element_tag = positive_int("element tag");
      const int64_t type = int_value("element type");
      const int64_t tag_count = int_value("tag count");
      if (tag_count < 0 || tag_count > 1024)
        in_.fail("element " + std::to_string(element_tag) + ": " + std::to_string(tag_count) + " tags");
      tags.resize(size_t(tag_count));
      for (int64_t& k : tags) k = int_value("element tag");
      read_element_22(type, element_tag, tags, nodes);
      ++seen;
    }
  }
}

// A 2.2 element: its tags are its physical group and elementary entity, then partitions.
void MshParser::read_element_22(int64_t type, uint64_t element_tag, const std::vector<int64_t>& tags,
                                std::vector<int64_t>& nodes) {
  const std::optional<GmshType> t = gmsh_type(type);
  const bool volume = t && t->dim == 3;
  const int64_t group = tags.empty() ? 0 : tags[0];
  if (volume && tags.size() >= 2) note_entity_group(tags[1], group);
  // Elements of every group are read, so that a copy in a group not asked for is known as one
  // (keep_wanted_groups_22 drops the others), but for types not read.
  const bool wanted = !volume || wanted_.empty() || volume_kind(type) || group_wanted(group);
  const uint64_t elements = out_.cells.cell_count(), copies = out_.element_copies.size();
  read_element(type, element_tag, nodes, wanted);
  if (wanted_.empty()) return;
  if (out_.cells.cell_count() > elements) element_group_.push_back(group);
  if (out_.element_copies.size() > copies) copy_groups_.push_back({out_.element_copies.back().second, group});
}

// 2.2 with --region: the elements of the groups asked for (in one of their copies' groups).
void MshParser::keep_wanted_groups_22() {
  std::map<int64_t, bool> wanted;
  const auto is_wanted = [&](int64_t g) {
    const auto [it, fresh] = wanted.emplace(g, false);
    if (fresh) it->second = group_wanted(g);
    return it->second;
  };
  MeshData& m = out_.cells;
  std::vector<bool> keep(m.cell_count());
  for (size_t e = 0; e < keep.size(); ++e) keep[e] = is_wanted(element_group_[e]);
  for (const auto& [e, g] : copy_groups_)
    if (is_wanted(g)) keep[e] = true;
  constexpr uint64_t kDropped = ~uint64_t(0);
  std::vector<uint64_t> new_index(keep.size(), kDropped);
  MeshData kept;
  kept.cell_offsets = {0};
  std::vector<uint64_t> tags;
  out_.kind_counts.clear();
  for (size_t e = 0; e < keep.size(); ++e) {
    if (!keep[e]) continue;
    new_index[e] = kept.cell_count();
    kept.connectivity.insert(kept.connectivity.end(), m.connectivity.begin() + ptrdiff_t(m.cell_offsets[e]),
                             m.connectivity.begin() + ptrdiff_t(m.cell_offsets[e + 1]));
    kept.cell_types.push_back(m.cell_types[e]);
    kept.cell_offsets.push_back(kept.connectivity.size());
    tags.push_back(out_.element_tags[e]);
    for (const VolumeKind& k : volume_kinds())
      if (k.vtk_type == m.cell_types[e]) ++out_.kind_counts[k.name];
  }
  std::vector<std::pair<uint64_t, uint64_t>> copies;
  for (const auto& [tag, e] : out_.element_copies)
    if (keep[e]) copies.push_back({tag, new_index[e]});
  m = std::move(kept);
  out_.element_tags = std::move(tags);
  out_.element_copies = std::move(copies);
}

// An elementary volume seen in a second physical group: copies of its elements follow, so every
// element read so far is indexed by its nodes, and every later one looked up.
void MshParser::note_entity_group(int64_t entity, int64_t group) {
  const auto [it, first] = entity_group_.emplace(entity, group);
  if (first || it->second == group || copies_possible_) return;
  copies_possible_ = true;
  for (uint64_t e = 0; e < out_.cells.cell_count(); ++e) index_element(e);
}

// FNV-1a over the nodes, then a final mix (the index uses the low bits, which a multiply alone
// takes from the nodes' low bits only).
uint64_t MshParser::nodes_hash(size_t first, size_t end, uint8_t vtk_type) const {
  uint64_t h = vtk_type;
  for (size_t i = first; i < end; ++i) h = (h ^ out_.cells.connectivity[i]) * 0x100000001b3ull;
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  return h ^ (h >> 33);
}

void MshParser::index_element(uint64_t e) {
  if (2 * (indexed_ + 1) > element_index_.size()) {
    std::vector<uint64_t> old = std::move(element_index_);
    element_index_.assign(std::max<size_t>(1024, 2 * old.size()), 0);
    for (uint64_t slot : old)
      if (slot) place_in_index(slot - 1);
  }
  place_in_index(e);
  ++indexed_;
}

void MshParser::place_in_index(uint64_t e) {
  const MeshData& m = out_.cells;
  const size_t mask = element_index_.size() - 1;
  size_t i = nodes_hash(m.cell_offsets[e], m.cell_offsets[e + 1], m.cell_types[e]) & mask;
  while (element_index_[i]) i = (i + 1) & mask;
  element_index_[i] = e + 1;
}

// The element read before with the nodes of connectivity[first..] (the one being read), in the
// same order, and of the same type.
std::optional<uint64_t> MshParser::earlier_copy(size_t first, uint8_t vtk_type) const {
  if (element_index_.empty()) return std::nullopt;
  const MeshData& m = out_.cells;
  const size_t end = m.connectivity.size(), mask = element_index_.size() - 1;
  for (size_t i = nodes_hash(first, end, vtk_type) & mask; element_index_[i]; i = (i + 1) & mask) {
    const uint64_t e = element_index_[i] - 1, b = m.cell_offsets[e];
    if (m.cell_types[e] == vtk_type && m.cell_offsets[e + 1] - b == end - first &&
        std::equal(m.connectivity.begin() + ptrdiff_t(first), m.connectivity.end(),
                   m.connectivity.begin() + ptrdiff_t(b)))
      return e;
  }
  return std::nullopt;
}

// --region: a physical group of volumes, asked for by its name or its number?
bool MshParser::group_wanted(int64_t group) {
  if (group <= 0) return false;  // 0: in no group
  groups_seen_.insert(group);
  const auto name = group_names_.find(group);
  bool wanted = false;
  for (size_t i = 0; i < wanted_.size(); ++i)
    if (wanted_[i] == std::to_string(group) || (name != group_names_.end() && wanted_[i] == name->second)) {
      matched_[i] = true;
      wanted = true;
    }
  if (wanted) out_.groups_read[group] = name == group_names_.end() ? "" : name->second;
  return wanted;
}

// 4.1: whether the elements of volume `entity` are read (with --region: it is in a group asked for).
bool MshParser::volume_wanted(int64_t entity) {
  if (wanted_.empty()) return true;
  if (!have_entities_) in_.fail("physical groups asked for (--region), but no $Entities before $Elements");
  const auto it = volume_groups_.find(entity);
  bool wanted = false;
  if (it != volume_groups_.end())
    for (int64_t g : it->second) wanted = group_wanted(g) || wanted;  // every group, for groups_read
  return wanted;
}

void MshParser::check_groups_found() const {
  std::set<int64_t> groups = groups_seen_;
  for (const auto& [group, name] : group_names_) groups.insert(group);
  for (const auto& [volume, of] : volume_groups_) groups.insert(of.begin(), of.end());
  std::vector<std::string> labels;
  for (int64_t g : groups) {
    const auto name = group_names_.find(g);
    labels.push_back(std::to_string(g) + (name == group_names_.end() ? "" : " (" + name->second + ")"));
  }
  for (size_t i = 0; i < wanted_.size(); ++i)
    if (!matched_[i])
      in_.fail("no physical group '" + wanted_[i] + "' of volume elements in this file (its groups of volumes: " +
               (labels.empty() ? "none" : joined(labels)) + ")");
}

// "numPhysicalNames", then "dimension physicalTag \"name\"" per line (ascii in binary files too).
void MshParser::read_physical_names() {
  const uint64_t n = ascii_count("physical name count");
  in_.require_fits(n, 6, "$PhysicalNames");
  for (uint64_t i = 0; i < n; ++i) {
    const int64_t dim = in_.integer("physical group dimension");
    const int64_t group = in_.integer("physical group tag");
    std::string name = string_tag();
    if (dim == 3) group_names_[group] = std::move(name);
  }
  expect_end("$PhysicalNames");
}

// 4.1 $Entities: "numPoints numCurves numSurfaces numVolumes", then per point "tag x y z
// numPhysicalTags physicalTag...", per curve, surface and volume "tag minX minY minZ maxX maxY
// maxZ numPhysicalTags physicalTag... numBounding boundingTag...". $PartitionedEntities (a
// partitioned mesh, whose elements lie on these entities): first "numPartitions", then
// "numGhostEntities" and "ghostTag partition" per ghost entity, then the entities as above with
// "parentDim parentTag numPartitions partitionTag..." after each tag. The volumes' groups are kept.
void MshParser::read_entities(bool partitioned) {
  const char* section = partitioned ? "$PartitionedEntities" : "$Entities";
  if (partitioned) {
    count("partition count");
    const uint64_t ghosts = count("ghost entity count");
    in_.require_fits(ghosts, binary_ ? 8 : 4, section);
    for (uint64_t g = 0; g < ghosts; ++g) {
      int_value("ghost entity tag");
      int_value("ghost entity partition");
    }
    volume_groups_.clear();  // the elements lie on the partitions' entities, not the model's
  }
  uint64_t counts[4];
  for (uint64_t& c : counts) c = count("entity count");
  std::vector<int64_t> groups;
  for (int dim = 0; dim < 4; ++dim) {
    const uint64_t numbers = (dim == 0 ? 5 : 9) + (partitioned ? 3 : 0);  // the fewest an entity has
    in_.require_fits(counts[dim], binary_ ? 4 * numbers + 12 : 2 * numbers, section);
    for (uint64_t e = 0; e < counts[dim]; ++e) {
      const int64_t tag = read_entity(dim, partitioned, groups);
      if (dim == 3) volume_groups_[tag] = groups;
    }
  }
  expect_end(section);
  have_entities_ = true;
}

// One entity of read_entities' list: its tag, its physical groups put in `groups`.
int64_t MshParser::read_entity(int dim, bool partitioned, std::vector<int64_t>& groups) {
  const auto tag_list = [&](std::vector<int64_t>* into) {
    const uint64_t n = count("entity tag count");
    in_.require_fits(n, binary_ ? 4 : 2, "$Entities tags");
    if (into) into->clear();
    for (uint64_t i = 0; i < n; ++i) {
      const int64_t t = int_value("entity tag");
      if (into) into->push_back(t);
    }
  };
  const int64_t tag = int_value("entity tag");
  if (partitioned) {
    int_value("parent dimension");
    int_value("parent tag");
    tag_list(nullptr);  // its partitions
  }
  for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) real_value("entity coordinate");
  tag_list(&groups);
  if (dim > 0) tag_list(nullptr);  // the entities bounding it
  return tag;
}

void MshParser::finish_elements() {
  if (!v41_ && !wanted_.empty()) keep_wanted_groups_22();
  if (!unread_volumes_.empty()) {
    const auto [type, n] = *unread_volumes_.begin();
    in_.fail("volume element type " + std::to_string(type) + " x " + std::to_string(n) + " is not read" +
             (type == 14 ? " (the 14-node pyramid: VTK has no such cell; the 13-node one, type 19, is read)"
                         : " (types 4, 5, 6, 7, 11, 12, 13, 17, 18, 19 are)"));
  }
  if (!out_.elements.build(out_.element_tags, out_.element_copies)) in_.fail("an element tag given twice in $Elements");
  have_elements_ = true;
}

// A string tag: a line, in double quotes (a name may hold blanks).
std::string MshParser::string_tag() {
  std::string_view s = in_.line();
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return std::string(s);
}

// "$NodeData" or "$ElementData": string tags (the view's name first), real tags (its time
// first), integer tags (time step, components, entries, [partition]), then "tag value..." per
// entry (binary: an int tag, then doubles; Gmsh writes an int here even in 4.1, whose manual
// does not give the size).
void MshParser::read_view(bool cells) {
  const char* section = cells ? "$ElementData" : "$NodeData";
  if (!(cells ? have_elements_ : have_nodes_)) in_.fail(std::string(section) + " before the mesh");
  const int64_t strings = in_.integer("string tag count");
  if (strings < 0 || strings > 64) in_.fail("string tag count " + std::to_string(strings));
  in_.skip_line();
  std::string name;
  for (int64_t i = 0; i < strings; ++i) {
    std::string s = string_tag();
    if (i == 0) name = s;
  }
  const int64_t reals = in_.integer("real tag count");
  if (reals < 0 || reals > 64) in_.fail("real tag count " + std::to_string(reals));
  double time = 0;
  for (int64_t i = 0; i < reals; ++i) {
    const double r = in_.real("real tag");
    if (i == 0) time = r;
  }
  const int64_t ints = in_.integer("integer tag count");
  if (ints < 3 || ints > 64)
    in_.fail(std::string(section) + " with " + std::to_string(ints) +
             " integer tags (3 or more: step, components, count)");
  int64_t tags[3] = {};
  for (int64_t i = 0; i < ints; ++i) {
    const int64_t v = in_.integer("integer tag");
    if (i < 3) tags[i] = v;
  }
  const auto [step, components, entries] = tags;
  if (name.empty()) name = cells ? "element_data" : "node_data";
  if (components != 1 && components != 3 && components != 9)
    in_.fail(std::string(section) + " '" + name + "': " + std::to_string(components) +
             " components (1, 3 or 9 are read)");
  if (entries < 0) in_.fail(std::string(section) + " '" + name + "': " + std::to_string(entries) + " entries");
  start_binary();
  const uint64_t c = uint64_t(components);
  in_.require_fits(uint64_t(entries), binary_ ? 4 + 8 * c : 2 * (1 + c), std::string(section) + " '" + name + "'");

  auto it = std::find_if(out_.views.begin(), out_.views.end(),
                         [&](const View& v) { return v.name == name && v.cells == cells; });
  if (it == out_.views.end()) it = out_.views.insert(out_.views.end(), View{name, cells, int(components), {}});
  if (it->components != components)
    in_.fail(std::string(section) + " '" + name + "': " + std::to_string(components) + " components, earlier " +
             std::to_string(it->components));
  const uint64_t tuples = cells ? out_.element_tags.size() : out_.points.size();
  ViewStep& s = it->steps[step];
  if (s.values.empty()) {
    // Each step of a view holds values for the whole mesh, so many tiny blocks of new step
    // indices could ask for far more memory than the file holds values: a step must be paid for
    // by the file's bytes (each of a volume's nodes or elements takes 2 bytes or more in a view).
    view_tuples_ += tuples;
    if (view_tuples_ > (in_.position() + in_.remaining()) / 2)
      in_.fail(std::string(section) + " '" + name + "' step " + std::to_string(step) +
               ": more view steps than the file holds values for");
    s.time = time;  // a step's later partitions repeat its time
    s.values.assign(tuples * c, std::numeric_limits<double>::quiet_NaN());
    s.given.assign(tuples, 0);
  }
  for (int64_t e = 0; e < entries; ++e) {
    const int64_t t = int_value(cells ? "element tag" : "node tag");
    const std::optional<uint64_t> index = cells ? out_.elements.find(t) : out_.nodes.find(t);
    for (uint64_t k = 0; k < c; ++k) {
      const double v = real_value("value");
      // Values of elements not read (surfaces) are dropped, and so are those of nodes the file
      // does not hold: Gmsh's 2.2 writer gives such a node (one no element saved uses) as -1.
      if (index) s.values[*index * c + k] = v;
    }
    if (index) s.given[*index] = 1;
  }
  expect_end(section);
}

void MshParser::read_section(std::string_view name) {
  if (name == "$Nodes") return read_nodes();
  if (name == "$Elements") return read_elements();
  if (name == "$NodeData") return read_view(false);
  if (name == "$ElementData") return read_view(true);
  if (!wanted_.empty()) {  // what --region needs; other files skip these sections as before
    if (name == "$PhysicalNames") return read_physical_names();
    if ((name == "$Entities" || name == "$PartitionedEntities") && v41_)
      return read_entities(name == "$PartitionedEntities");
  }
  if (name == "$ElementNodeData") {
    // Values per element node (discontinuous fields): not point data; left out, and said so.
    const int64_t strings = in_.integer("string tag count");
    in_.skip_line();
    const std::string view = strings > 0 ? string_tag() : "unnamed";
    const std::string note = "$ElementNodeData '" + view + "' left out";
    if (std::find(out_.left_out.begin(), out_.left_out.end(), note) == out_.left_out.end())
      out_.left_out.push_back(note);
  }
  skip_section(name);
}

GmshContents MshParser::parse() {
  read_format();
  while (const std::optional<std::string_view> word = in_.try_word()) {
    if (word->empty() || word->front() != '$')
      in_.fail("expected a section ($Nodes, ...), found '" + std::string(word->substr(0, 20)) + "'");
    in_.skip_line();
    read_section(*word);
  }
  if (!have_nodes_ || !have_elements_) in_.fail("no $Nodes and $Elements sections");
  check_groups_found();
  if (out_.element_tags.empty())
    in_.fail(wanted_.empty() ? "no volume elements (only points, lines, triangles or quadrangles)"
                             : "no volume elements in the physical groups asked for");
  return std::move(out_);
}

}  // namespace

struct GmshFile::Impl {
  std::string file;
  GmshContents contents;
  std::vector<std::pair<int64_t, double>> steps;  // the views' step indices, sorted, and times
  mutable SplitMemo quadratic_split;              // the last step's, for the next

  // Every node of a volume element and every volume element must have a value in each step of
  // each view (a file may hold values of other nodes and elements too).
  void check_views() const {
    std::vector<uint8_t> used(contents.points.size(), 0);
    for (uint64_t n : contents.cells.connectivity) used[n] = 1;
    for (const View& v : contents.views)
      for (const auto& [step, s] : v.steps)
        for (size_t i = 0; i < s.given.size(); ++i)
          if (!s.given[i] && (v.cells || used[i]))
            input_error(file, std::string(v.cells ? "$ElementData" : "$NodeData") + " '" + v.name + "' step " +
                                  std::to_string(step) + ": no value for " + (v.cells ? "element" : "node") + " tag " +
                                  std::to_string((v.cells ? contents.element_tags : contents.node_tags)[i]) +
                                  " of the volume");
  }

  // The manual does not say what a step index whose views give different times means: the first
  // view's time is taken. Views of one step (which hold at every step) give steps only in a file
  // with no others.
  void collect_steps() {
    std::map<int64_t, double> times;
    const bool series =
        std::any_of(contents.views.begin(), contents.views.end(), [](const View& v) { return v.steps.size() > 1; });
    for (const View& v : contents.views)
      if (!series || v.steps.size() > 1)
        for (const auto& [step, s] : v.steps) times.emplace(step, s.time);
    steps.assign(times.begin(), times.end());
    if (steps.empty()) steps.push_back({0, 0.0});
  }

  // The view's values at the file's step `index`: a view of one step holds at every step.
  static const ViewStep* at_step(const View& v, int64_t index) {
    if (v.steps.size() == 1) return &v.steps.begin()->second;
    const auto it = v.steps.find(index);
    return it == v.steps.end() ? nullptr : &it->second;
  }
};

GmshFile::GmshFile(const fs::path& file, const std::vector<std::string>& groups) : impl_(std::make_unique<Impl>()) {
  impl_->file = file.string();
  impl_->contents = MshParser(file, groups).parse();
  impl_->check_views();
  impl_->collect_steps();
}

GmshFile::~GmshFile() = default;

size_t GmshFile::step_count() const { return impl_->steps.size(); }

double GmshFile::step_time(size_t step) const { return impl_->steps.at(step).second; }

MeshData GmshFile::read_step(size_t step) const {
  const GmshContents& c = impl_->contents;
  MeshData m;
  m.points = c.points;
  m.cell_types = c.cells.cell_types;
  m.cell_offsets = c.cells.cell_offsets;
  m.connectivity = c.cells.connectivity;
  for (const View& v : c.views)
    if (const ViewStep* s = Impl::at_step(v, impl_->steps.at(step).first))
      (v.cells ? m.cell_data : m.point_data).push_back({v.name, v.components, s->values});
  if (!c.groups_read.empty()) drop_unused_points(m);  // the nodes of the groups not read
  split_quadratic_cells(m, impl_->file, impl_->steps.size() > 1 ? &impl_->quadratic_split : nullptr);
  check_mesh(m, impl_->file);
  return m;
}

std::string GmshFile::summary() const {
  const GmshContents& c = impl_->contents;
  std::string s = c.format + ":";
  bool first = true;
  for (const auto& [kind, n] : c.kind_counts) {
    s.append(first ? " " : ", ").append(kind).append(" x " + std::to_string(n));
    first = false;
  }
  if (!c.groups_read.empty()) {
    s += "; physical groups read:";
    for (const auto& [group, name] : c.groups_read)
      s += " " + std::to_string(group) + (name.empty() ? "" : " (" + name + ")");
  }
  if (!c.element_copies.empty())
    s += "; " + std::to_string(c.element_copies.size()) + " copies of elements in a second physical group read once";
  for (const std::string& note : c.left_out) s += "; " + note;
  return s;
}

}  // namespace vs
