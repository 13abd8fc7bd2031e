#include "volstream/io/cgns.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <span>

#include "volstream/core/error.h"
#include "volstream/core/release.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/shared_library.h"
#include "volstream/io/solver_files.h"
#include "volstream/umesh/mesh_pieces.h"
#include "volstream/umesh/polyhedra.h"
#include "volstream/umesh/quadratic.h"

#ifdef VOLSTREAM_HAVE_CGNS
#include <cgns_io.h>
#include <cgnslib.h>
#endif

namespace vs {
namespace fs = std::filesystem;

#ifndef VOLSTREAM_HAVE_CGNS

bool cgns_supported() { return false; }
struct CgnsFile::Impl {};
CgnsFile::CgnsFile(const fs::path& file, const std::vector<std::string>&) {
  input_error(file.string(),
              "this volstream was built without the CGNS library, which CGNS files need "
              "(Debian: apt-get install libcgns-dev, then build again)");
}
CgnsFile::~CgnsFile() = default;
size_t CgnsFile::step_count() const { return 0; }
double CgnsFile::step_time(size_t) const { return 0; }
MeshData CgnsFile::read_step(size_t) { return {}; }
std::string CgnsFile::summary() const { return {}; }

#else

bool cgns_supported() { return true; }

namespace {

// The CGNS functions the reader calls, from the library opened at the first CGNS file
// (io/shared_library.h: linked, it cost every command ~20 ms of start).
// clang-format off
#define VOLSTREAM_CGNS_FUNCTIONS(X)                                                                \
  X(cg_open) X(cg_close) X(cg_get_error) X(cg_nbases) X(cg_base_read) X(cg_nzones) X(cg_zone_read) \
  X(cg_zone_type) X(cg_coord_read) X(cg_nsections) X(cg_section_read) X(cg_ElementDataSize)        \
  X(cg_elements_read) X(cg_poly_elements_read) X(cg_npe) X(cg_nsols) X(cg_sol_info) X(cg_nfields)  \
  X(cg_field_info) X(cg_field_read) X(cg_goto) X(cg_rind_read) X(cg_narrays) X(cg_array_info)      \
  X(cg_array_read) X(cg_array_read_as) X(cg_ziter_read) X(cg_biter_read) X(cg_get_cgio)            \
  X(cg_root_id) X(cgio_get_node_id) X(cgio_release_id) X(cgio_get_dimensions)                      \
  X(cgio_read_all_data_type) X(cg_ElementTypeName) X(cg_GridLocationName)
// clang-format on
VOLSTREAM_LIBRARY_CALLS(CgnsCalls, VOLSTREAM_CGNS_FUNCTIONS);

const CgnsCalls& cgns() {
  return hdf5_reader_calls<CgnsCalls>(VOLSTREAM_CGNS_SONAME,
                                      "CGNS files need it (Debian: apt-get install libcgns-dev)");
}

// A volume element type of CGNS and what it is in VTK: the cell type and, for each VTK node, the
// CGNS node (0-based) that is it. CGNS's orders (the SIDS) are VTK's but for: the wedge, whose
// first triangle faces its second; the quadratic hexahedron's and wedge's mid-edge nodes, bottom,
// vertical, top (io/solver_files.h); and HEXA_27's face centres, -z, -y, +x, +y, -x, +z before
// the body's (VTK: -x, +x, -y, +y, -z, +z).
struct ElementKind {
  CGNS_ENUMT(ElementType_t) type;
  uint8_t vtk_type;
  std::vector<int> vtk_from_cgns;  // empty: the same order
};

const std::vector<ElementKind>& element_kinds() {
  static const std::vector<ElementKind> kinds = {
      {CGNS_ENUMV(TETRA_4), 10, {}},
      {CGNS_ENUMV(PYRA_5), 14, {}},
      {CGNS_ENUMV(PENTA_6), 13, {kWedgeFacingInward.begin(), kWedgeFacingInward.end()}},
      {CGNS_ENUMV(HEXA_8), 12, {}},
      {CGNS_ENUMV(TETRA_10), uint8_t(QuadraticCell::tet10), {}},
      {CGNS_ENUMV(PYRA_13), uint8_t(QuadraticCell::pyramid13), {}},
      {CGNS_ENUMV(PENTA_15),
       uint8_t(QuadraticCell::wedge15),
       {kWedge15FacingInwardBottomVerticalTop.begin(), kWedge15FacingInwardBottomVerticalTop.end()}},
      {CGNS_ENUMV(HEXA_20),
       uint8_t(QuadraticCell::hex20),
       {kHex20BottomVerticalTop.begin(), kHex20BottomVerticalTop.end()}},
      {CGNS_ENUMV(HEXA_27), uint8_t(QuadraticCell::hex27), {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 16, 17,
                                                            18, 19, 12, 13, 14, 15, 24, 22, 21, 23, 20, 25, 26}},
  };
  return kinds;
}

// Faces, edges and nodes (boundary sections): left out.
bool is_lower_dimensional(int type) {
  return (type >= 2 && type <= 9) || (type >= 24 && type <= 28) || (type >= 40 && type <= 44);
}

std::string type_name(int type) {
  return type >= 0 && type < NofValidElementTypes ? cgns().cg_ElementTypeName(CGNS_ENUMT(ElementType_t)(type))
                                                  : "element type " + std::to_string(type);
}

// An index range of a zone's vertices or cells: (1, ...) to the counts.
struct Range {
  std::array<cgsize_t, 3> min{1, 1, 1}, max{1, 1, 1};
  // Values in the range; 0 where a damaged file's counts multiply past any file.
  size_t size() const {
    size_t n = 1;
    for (cgsize_t m : max)
      if (m < 1 || __builtin_mul_overflow(n, size_t(m), &n) || n > (size_t(1) << 40)) return 0;
    return n;
  }
};

}  // namespace

struct CgnsFile::Impl {
  // An NGON_n section: the faces numbered first .. last are faces first_face, ... of the zone.
  struct FaceSection {
    cgsize_t first = 0, last = 0;
    uint64_t first_face = 0;
  };
  struct Zone {
    int index = 0;
    std::string name;
    bool structured = false;
    Range vertices, cells;
    MeshData topology;                                   // the zone's points and kept cells, VTK order; no data
    std::vector<cgsize_t> cell_number;                   // unstructured: each kept cell's element number
    std::vector<size_t> cell_value_index;                // and where its CellCenter value is (per_kept_cell)
    PolyhedronFaces faces;                               // the faces of its NFACE_n cells (kVtkPolyhedron)
    std::vector<FaceSection> face_sections;              // where faces.face_offsets has each NGON_n section
    std::vector<std::array<cgsize_t, 2> > face_parents;  // each face's ParentElements, where all have them
    mutable SplitMemo polyhedra_split;                   // the last step's, for the next
    std::vector<std::string> solution_at_step;           // FlowSolutionPointers; empty: every solution, one step
  };

  std::string file;
  int fn = -1, base = 0;
  std::string base_name;  // the node path's first part (read_parent_elements)
  std::vector<Zone> zones;
  std::vector<std::string> wanted;  // the zones to read, by name (empty: all)
  std::vector<double> times{0.0};
  std::map<std::string, uint64_t> element_counts;  // of structured zones' hexahedra, and cells by ParentElements
  std::vector<uint64_t> elements_of_type = std::vector<uint64_t>(NofValidElementTypes);
  mutable SplitMemo quadratic_split;  // the last step's, for the next

  ~Impl() {
    if (fn >= 0) cgns().cg_close(fn);
  }

  void check(int status, const std::string& what) const {
    if (status != CG_OK) input_error(file, what + ": " + cgns().cg_get_error());
  }

  void open(const fs::path& path) {
    file = path.string();
    check(cgns().cg_open(file.c_str(), CG_MODE_READ, &fn), "not a CGNS file");
    find_3d_base();
    int count = 0;
    check(cgns().cg_nzones(fn, base, &count), "zones");
    input_check(count > 0, file, "a base without zones");
    std::vector<std::string> names;
    for (int z = 1; z <= count; ++z) {
      names.push_back(zone_name(z));
      if (is_wanted(names.back())) zones.push_back(read_zone(z));
    }
    for (const std::string& w : wanted)
      if (std::find(names.begin(), names.end(), w) == names.end())
        input_error(file,
                    "no zone '" + w + "' in this file's base " + base_name + " (its zones: " + joined(names) + ")");
    read_times();
  }

  bool is_wanted(const std::string& zone) const {
    return wanted.empty() || std::find(wanted.begin(), wanted.end(), zone) != wanted.end();
  }

  std::string zone_name(int z) const {
    char name[33] = {};
    cgsize_t size[9] = {};
    check(cgns().cg_zone_read(fn, base, z, name, size), "zone");
    return name;
  }

  void find_3d_base() {
    int bases = 0;
    check(cgns().cg_nbases(fn, &bases), "bases");
    for (int b = 1; b <= bases && !base; ++b) {
      char name[33] = {};
      int cell_dim = 0, phys_dim = 0;
      check(cgns().cg_base_read(fn, b, name, &cell_dim, &phys_dim), "base");
      if (cell_dim == 3 && phys_dim == 3) {
        base = b;
        base_name = name;
      }
    }
    input_check(base > 0, file, "no base of cell dimension 3: volstream renders volumes");
  }

  Zone read_zone(int z) {
    Zone zone;
    zone.index = z;
    char name[33] = {};
    cgsize_t size[9] = {};
    CGNS_ENUMT(ZoneType_t) type;
    check(cgns().cg_zone_type(fn, base, z, &type), "zone type");
    check(cgns().cg_zone_read(fn, base, z, name, size), "zone");
    zone.name = name;
    zone.structured = type == CGNS_ENUMV(Structured);
    input_check(zone.structured || type == CGNS_ENUMV(Unstructured), file, "zone " + zone.name + " of unknown type");
    for (int a = 0; a < (zone.structured ? 3 : 1); ++a) {
      zone.vertices.max[size_t(a)] = size[a];
      zone.cells.max[size_t(a)] = size[(zone.structured ? 3 : 1) + a];
      input_check(size[a] >= (zone.structured ? 2 : 1) && zone.cells.max[size_t(a)] >= 1, file,
                  "zone " + zone.name + ": no cells");
    }
    input_check(zone.vertices.size() > 0 && zone.cells.size() > 0, file,
                "zone " + zone.name + ": more nodes or cells than any file holds");
    read_coordinates(zone);
    if (zone.structured)
      structured_cells(zone);
    else
      read_sections(zone);
    read_solution_pointers(zone);
    return zone;
  }

  // Field or coordinate `name` of zone z over `range`, as doubles.
  std::vector<double> read_array(const Zone& zone, int solution, const std::string& name, const Range& range) const {
    std::vector<double> v(range.size());
    cgsize_t min[3], max[3];
    std::copy(range.min.begin(), range.min.end(), min);
    std::copy(range.max.begin(), range.max.end(), max);
    if (solution == 0)
      check(cgns().cg_coord_read(fn, base, zone.index, name.c_str(), CGNS_ENUMV(RealDouble), min, max, v.data()),
            "zone " + zone.name + ": " + name);
    else
      check(cgns().cg_field_read(fn, base, zone.index, solution, name.c_str(), CGNS_ENUMV(RealDouble), min, max,
                                 v.data()),
            "zone " + zone.name + ": field " + name);
    return v;
  }

  void read_coordinates(Zone& zone) {
    std::array<std::vector<double>, 3> axes;
    const char* kNames[] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
    for (size_t a = 0; a < 3; ++a) axes[a] = read_array(zone, 0, kNames[a], zone.vertices);
    zone.topology.points.resize(zone.vertices.size());
    for (size_t i = 0; i < zone.topology.points.size(); ++i)
      zone.topology.points[i] = vec3d(axes[0][i], axes[1][i], axes[2][i]);
  }

  // A structured zone's cells as hexahedra (i fastest), turned the right way round for VTK when
  // its index axes are left-handed.
  void structured_cells(Zone& zone) {
    const cgsize_t ni = zone.vertices.max[0], nj = zone.vertices.max[1], nk = zone.vertices.max[2];
    auto node = [&](cgsize_t i, cgsize_t j, cgsize_t k) { return uint64_t(i + ni * (j + nj * k)); };
    const auto& p = zone.topology.points;
    const vec3d di = p[node(1, 0, 0)] - p[0], dj = p[node(0, 1, 0)] - p[0], dk = p[node(0, 0, 1)] - p[0];
    const bool left_handed = dot(cross(di, dj), dk) < 0;
    MeshData& t = zone.topology;
    t.cell_offsets = {0};
    for (cgsize_t k = 0; k + 1 < nk; ++k)
      for (cgsize_t j = 0; j + 1 < nj; ++j)
        for (cgsize_t i = 0; i + 1 < ni; ++i) {
          const cgsize_t lo = left_handed ? k + 1 : k, hi = left_handed ? k : k + 1;
          for (cgsize_t kk : {lo, hi})
            for (const auto& [a, b] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}})
              t.connectivity.push_back(node(i + a, j + b, kk));
          t.cell_types.push_back(12);
          t.cell_offsets.push_back(t.connectivity.size());
        }
    element_counts["HEXA_8 (structured)"] += t.cell_count();
  }

  // The faces of NGON_n sections first, because an NFACE_n section's cells may name faces of a
  // section after it.
  void read_sections(Zone& zone) {
    int sections = 0;
    check(cgns().cg_nsections(fn, base, zone.index, &sections), "zone " + zone.name + ": sections");
    zone.topology.cell_offsets = {0};
    for (bool faces : {true, false})
      for (int s = 1; s <= sections; ++s) read_section(zone, s, faces);
    if (zone.topology.cell_count() == 0 && !zone.face_sections.empty()) cells_from_parents(zone);
    input_check(zone.topology.cell_count() > 0, file, "zone " + zone.name + ": no volume elements");
    zone.cell_value_index = ranks(zone.cell_number);
  }

  // An NGON_n section's ParentElements (its faces' left and right cells, 0 for none), kept while
  // every face section so far has them. Read through the file's node tree (cgns_io.h): the
  // library's element reads give them only beside ParentElementsPosition.
  void read_parent_elements(Zone& zone, const std::string& section, size_t faces, const std::string& where) {
    if (zone.face_parents.size() != zone.faces.face_offsets.size() - 1 - faces) return;  // a section before had none
    int cgio = 0;
    double root = 0, node = 0;
    const std::string path = "/" + base_name + "/" + zone.name + "/" + section + "/ParentElements";
    if (cgns().cg_get_cgio(fn, &cgio) != CG_OK || cgns().cg_root_id(fn, &root) != CG_OK ||
        cgns().cgio_get_node_id(cgio, root, path.c_str(), &node) != CGIO_ERR_NONE)
      return;
    // The node id is an open HDF5 object: released on every way out, or HDF5 finds it open at
    // exit (and complains on stderr).
    const struct Release {
      int cgio;
      double node;
      ~Release() { cgns().cgio_release_id(cgio, node); }
    } release{cgio, node};
    int dimensions = 0;
    cgsize_t size[CGIO_MAX_DIMENSIONS] = {};
    if (cgns().cgio_get_dimensions(cgio, node, &dimensions, size) != CGIO_ERR_NONE ||
        !(dimensions == 2 && size[0] == cgsize_t(faces) && size[1] == 2))
      input_error(file, where + ": ParentElements not of " + std::to_string(faces) + " x 2 cells");
    std::vector<cgsize_t> columns(2 * faces);  // the left cells, then the right
    if (cgns().cgio_read_all_data_type(cgio, node, sizeof(cgsize_t) == 8 ? "I8" : "I4", columns.data()) !=
        CGIO_ERR_NONE)
      input_error(file, where + ": ParentElements unreadable");
    for (size_t f = 0; f < faces; ++f) zone.face_parents.push_back({columns[f], columns[faces + f]});
  }

  // A zone of NGON_n faces alone: its cells are the element numbers the faces' ParentElements
  // name (numbered after the faces, or 1.., as writers differ), each the polyhedron of the faces
  // naming it, in the order of their numbers.
  void cells_from_parents(Zone& zone) {
    const std::string where = "zone " + zone.name;
    if (zone.face_parents.size() != zone.faces.face_offsets.size() - 1)
      input_error(file, where + ": NGON_n faces without an NFACE_n section or the faces' ParentElements");
    std::vector<cgsize_t> numbers;
    for (const auto& parents : zone.face_parents)
      for (cgsize_t c : parents) {
        if (c < 0) input_error(file, where + ": ParentElements name cell " + std::to_string(c));
        if (c > 0) numbers.push_back(c);
      }
    std::sort(numbers.begin(), numbers.end());
    numbers.erase(std::unique(numbers.begin(), numbers.end()), numbers.end());
    if (numbers.size() != zone.cells.size())
      input_error(file, where + ": the faces' ParentElements name " + std::to_string(numbers.size()) +
                            " cells, the zone has " + std::to_string(zone.cells.size()));
    std::vector<FaceCells> sides(zone.face_parents.size());
    const auto index = [&](cgsize_t c) {  // 1-based place among the numbers; 0 for none
      return c == 0 ? 0 : uint64_t(std::lower_bound(numbers.begin(), numbers.end(), c) - numbers.begin()) + 1;
    };
    for (size_t f = 0; f < sides.size(); ++f) {
      const auto [left, right] = zone.face_parents[f];
      if (left == right) input_error(file, where + ": face " + std::to_string(f + 1) + " has one cell on both sides");
      sides[f] = {index(left), index(right)};
    }
    zone.faces = polyhedra_from_face_cells(std::move(zone.faces.face_offsets), std::move(zone.faces.face_vertices),
                                           sides, numbers.size(), file);
    release(zone.face_parents);
    MeshData& t = zone.topology;
    t.cell_types.assign(numbers.size(), kVtkPolyhedron);
    t.cell_offsets.assign(numbers.size() + 1, 0);
    zone.cell_number = std::move(numbers);
    element_counts["polyhedra (NGON_n ParentElements)"] += zone.cell_number.size();
  }

  // Each number's place among them in increasing order.
  static std::vector<size_t> ranks(const std::vector<cgsize_t>& numbers) {
    std::vector<size_t> order(numbers.size()), rank(numbers.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return numbers[a] < numbers[b]; });
    for (size_t r = 0; r < order.size(); ++r) rank[order[r]] = r;
    return rank;
  }

  // Section s's elements, if it holds faces (NGON_n) and `faces` is set, or holds others and it
  // is not.
  void read_section(Zone& zone, int s, bool faces) {
    char name[33] = {};
    CGNS_ENUMT(ElementType_t) type;
    cgsize_t start = 0, end = 0;
    int boundary = 0, parents = 0;
    check(cgns().cg_section_read(fn, base, zone.index, s, name, &type, &start, &end, &boundary, &parents),
          "zone " + zone.name + ": section");
    const std::string where = "zone " + zone.name + ", section " + name;
    if (is_lower_dimensional(type) || faces != (type == CGNS_ENUMV(NGON_n))) return;
    input_check(start >= 1 && end >= start, file, where + ": bad element range");
    cgsize_t data_size = 0;
    check(cgns().cg_ElementDataSize(fn, base, zone.index, s, &data_size), where);
    input_check(data_size >= 0, file, where + ": bad element data size");
    input_check(end - start < cgsize_t(1) << 30, file, where + ": too many elements");
    std::vector<cgsize_t> data(static_cast<size_t>(data_size));
    if (type == CGNS_ENUMV(MIXED) || type == CGNS_ENUMV(NGON_n) || type == CGNS_ENUMV(NFACE_n)) {
      std::vector<cgsize_t> offsets(size_t(end - start) + 2);
      check(cgns().cg_poly_elements_read(fn, base, zone.index, s, data.data(), offsets.data(), nullptr), where);
      if (type == CGNS_ENUMV(MIXED))
        add_fixed_elements(zone, type, data, start, end, where);
      else
        add_polyhedral_elements(zone, type, data, offsets, start, where);
      if (type == CGNS_ENUMV(NGON_n)) read_parent_elements(zone, name, size_t(end - start) + 1, where);
      return;
    }
    check(cgns().cg_elements_read(fn, base, zone.index, s, data.data(), nullptr), where);
    add_fixed_elements(zone, type, data, start, end, where);
  }

  // A section of one type, or MIXED (each element's type before its nodes).
  void add_fixed_elements(Zone& zone, int type, const std::vector<cgsize_t>& data, cgsize_t start, cgsize_t end,
                          const std::string& where) {
    size_t at = 0;
    for (cgsize_t e = start; e <= end; ++e) {
      const int element_type = type == CGNS_ENUMV(MIXED) ? int(next(data, at, where)) : type;
      int nodes = 0;
      const bool known = element_type >= 0 && element_type < NofValidElementTypes &&
                         cgns().cg_npe(CGNS_ENUMT(ElementType_t)(element_type), &nodes) == CG_OK && nodes > 0;
      if (!known)
        input_error(file,
                    where + ": element " + std::to_string(e) + " of unknown type " + std::to_string(element_type));
      if (at + size_t(nodes) > data.size()) input_error(file, where + ": element data cut short");
      if (!is_lower_dimensional(element_type)) add_element(zone, element_type, data.data() + at, e, where);
      at += size_t(nodes);
    }
  }

  // NGON_n: faces, each its nodes in order around it; NFACE_n: polyhedra, each its faces' element
  // numbers (negative where the face's normal points into the cell, which the split does not
  // need: it orients each piece itself).
  void add_polyhedral_elements(Zone& zone, int type, const std::vector<cgsize_t>& data,
                               const std::vector<cgsize_t>& offsets, cgsize_t start, const std::string& where) {
    const uint64_t first_face = zone.faces.face_offsets.size() - 1;
    for (size_t e = 0; e + 1 < offsets.size(); ++e) {
      const cgsize_t begin = offsets[e], end = offsets[e + 1], number = start + cgsize_t(e);
      if (!(begin >= 0 && begin <= end && size_t(end) <= data.size()))
        input_error(file, where + ": element " + std::to_string(number) + ": offsets outside the section's data");
      const std::span<const cgsize_t> values(data.data() + begin, size_t(end - begin));
      if (type == CGNS_ENUMV(NGON_n))
        add_face(zone, values, number, where);
      else
        add_polyhedron(zone, values, number, where);
    }
    if (type == CGNS_ENUMV(NGON_n))
      zone.face_sections.push_back({start, start + cgsize_t(offsets.size()) - 2, first_face});
  }

  void add_face(Zone& zone, std::span<const cgsize_t> nodes, cgsize_t number, const std::string& where) {
    const cgsize_t vertices = cgsize_t(zone.vertices.size());
    for (cgsize_t v : nodes) {
      if (!(v >= 1 && v <= vertices))
        input_error(file, where + ", face " + std::to_string(number) + ": node " + std::to_string(v) +
                              " out of range 1.." + std::to_string(vertices));
      zone.faces.face_vertices.push_back(saturated_face_index(int64_t(v - 1)));  // past 32 bits: refused by the split
    }
    zone.faces.face_offsets.push_back(zone.faces.face_vertices.size());
  }

  void add_polyhedron(Zone& zone, std::span<const cgsize_t> faces, cgsize_t number, const std::string& where) {
    for (cgsize_t f : faces) {
      const cgsize_t face = f == std::numeric_limits<cgsize_t>::min() ? 0 : f < 0 ? -f : f;  // 0: in no section
      zone.faces.cell_faces.push_back(saturated_face_index(int64_t(face_index(zone, face, number, where))));
    }
    zone.faces.cell_face_offsets.push_back(zone.faces.cell_faces.size());
    MeshData& t = zone.topology;
    t.cell_types.push_back(kVtkPolyhedron);
    t.cell_offsets.push_back(t.connectivity.size());
    zone.cell_number.push_back(number);
    ++elements_of_type[CGNS_ENUMV(NFACE_n)];
  }

  uint64_t face_index(const Zone& zone, cgsize_t face, cgsize_t cell, const std::string& where) const {
    for (const FaceSection& s : zone.face_sections)
      if (face >= s.first && face <= s.last) return s.first_face + uint64_t(face - s.first);
    input_error(
        file, where + ", cell " + std::to_string(cell) + ": face " + std::to_string(face) + " is in no NGON_n section");
  }

  cgsize_t next(const std::vector<cgsize_t>& data, size_t& at, const std::string& where) const {
    if (at >= data.size()) input_error(file, where + ": element data cut short");
    return data[at++];
  }

  void add_element(Zone& zone, int type, const cgsize_t* nodes, cgsize_t number, const std::string& where) {
    const auto& kinds = element_kinds();
    const auto kind =
        std::find_if(kinds.begin(), kinds.end(), [&](const ElementKind& k) { return int(k.type) == type; });
    if (kind == kinds.end())
      input_error(file, where + ": unsupported element type " + type_name(type) +
                            " (TETRA_4/10, PYRA_5/13, PENTA_6/15, HEXA_8/20/27 are read)");
    int count = 0;
    cgns().cg_npe(kind->type, &count);
    MeshData& t = zone.topology;
    const cgsize_t vertices = cgsize_t(zone.vertices.size());
    for (int k = 0; k < count; ++k) {
      const cgsize_t v = nodes[kind->vtk_from_cgns.empty() ? k : kind->vtk_from_cgns[size_t(k)]];
      if (!(v >= 1 && v <= vertices))
        input_error(file, where + ", element " + std::to_string(number) + ": node " + std::to_string(v) +
                              " out of range 1.." + std::to_string(vertices));
      t.connectivity.push_back(uint64_t(v - 1));
    }
    t.cell_types.push_back(kind->vtk_type);
    t.cell_offsets.push_back(t.connectivity.size());
    zone.faces.add_other_cell();
    zone.cell_number.push_back(number);
    ++elements_of_type[size_t(type)];
  }

  // The data array `name` of the node cg_goto() went to: its index, type and extents.
  struct ArrayInfo {
    int index = 0;
    CGNS_ENUMT(DataType_t) type;
    int dims = 0;
    cgsize_t extent[12] = {};
  };
  std::optional<ArrayInfo> array_named(const std::string& name) const {
    int arrays = 0;
    if (cgns().cg_narrays(&arrays) != CG_OK) return std::nullopt;
    for (int a = 1; a <= arrays; ++a) {
      char array_name[33] = {};
      ArrayInfo info;
      info.index = a;
      check(cgns().cg_array_info(a, array_name, &info.type, &info.dims, info.extent), "array");
      if (array_name == name) return info;
    }
    return std::nullopt;
  }

  // The character array `name` of the node cg_goto() went to, as rows of 32 characters.
  std::vector<std::string> string_rows(const std::string& name) const {
    const std::optional<ArrayInfo> a = array_named(name);
    if (!a) return {};
    input_check(a->type == CGNS_ENUMV(Character) && a->dims == 2 && a->extent[0] > 0 && a->extent[1] >= 0, file,
                name + " is not an array of names");
    std::string all(size_t(a->extent[0]) * size_t(a->extent[1]), '\0');
    check(cgns().cg_array_read(a->index, all.data()), name);
    std::vector<std::string> rows;
    for (cgsize_t r = 0; r < a->extent[1]; ++r)
      rows.push_back(trimmed_name(all.substr(size_t(r * a->extent[0]), size_t(a->extent[0]))));
    return rows;
  }

  void read_solution_pointers(Zone& zone) {
    char name[33] = {};
    if (cgns().cg_ziter_read(fn, base, zone.index, name) != CG_OK) return;
    if (cgns().cg_goto(fn, base, "Zone_t", zone.index, "ZoneIterativeData_t", 1, "end") != CG_OK) return;
    zone.solution_at_step = string_rows("FlowSolutionPointers");
  }

  void read_times() {
    char name[33] = {};
    int steps = 0;
    if (cgns().cg_biter_read(fn, base, name, &steps) != CG_OK || steps < 1) return;
    check(cgns().cg_goto(fn, base, "BaseIterativeData_t", 1, "end"), "BaseIterativeData");
    if (const std::optional<ArrayInfo> a = array_named("TimeValues")) {
      input_check(a->dims == 1 && a->extent[0] == steps, file, "TimeValues is not one time per step");
      times.assign(size_t(steps), 0.0);
      check(cgns().cg_array_read_as(a->index, CGNS_ENUMV(RealDouble), times.data()), "TimeValues");
    }
    if (times.size() != size_t(steps)) {  // steps without times: at 0, 1, ...
      times.resize(size_t(steps));
      for (int s = 0; s < steps; ++s) times[size_t(s)] = s;
    }
    for (double t : times) input_check(std::isfinite(t), file, "a time step at a time that is not finite");
    for (const Zone& z : zones)
      input_check(z.solution_at_step.empty() || z.solution_at_step.size() == times.size(), file,
                  "zone " + z.name + ": FlowSolutionPointers is not one solution per step");
  }

  // The solutions (1-based) zone z uses at step s: the one its FlowSolutionPointers names, or
  // every one.
  std::vector<int> solutions_at(const Zone& zone, size_t s) const {
    int count = 0;
    check(cgns().cg_nsols(fn, base, zone.index, &count), "zone " + zone.name + ": solutions");
    std::vector<int> out;
    for (int i = 1; i <= count; ++i) {
      char name[33] = {};
      CGNS_ENUMT(GridLocation_t) location;
      check(cgns().cg_sol_info(fn, base, zone.index, i, name, &location), "zone " + zone.name + ": solution");
      if (zone.solution_at_step.empty() || zone.solution_at_step[s] == name) out.push_back(i);
    }
    input_check(
        zone.solution_at_step.empty() || out.size() == 1, file,
        "zone " + zone.name + ": no solution " + (zone.solution_at_step.empty() ? "" : zone.solution_at_step[s]));
    return out;
  }

  // A solution's fields into m's point or cell data.
  void read_solution(const Zone& zone, int solution, MeshData& m) const {
    char name[33] = {};
    CGNS_ENUMT(GridLocation_t) location;
    check(cgns().cg_sol_info(fn, base, zone.index, solution, name, &location), "zone " + zone.name + ": solution");
    const std::string where = "zone " + zone.name + ", solution " + name;
    const bool at_cells = location == CGNS_ENUMV(CellCenter);
    input_check(at_cells || location == CGNS_ENUMV(Vertex), file,
                where + ": values at " + cgns().cg_GridLocationName(location) + " (Vertex and CellCenter are read)");
    int rind[6] = {};
    if (cgns().cg_goto(fn, base, "Zone_t", zone.index, "FlowSolution_t", solution, "end") == CG_OK &&
        cgns().cg_rind_read(rind) == CG_OK)
      input_check(std::all_of(rind, rind + 6, [](int r) { return r == 0; }), file,
                  where + ": rind planes are not read");
    int fields = 0;
    check(cgns().cg_nfields(fn, base, zone.index, solution, &fields), where);
    std::vector<std::string> names;
    for (int f = 1; f <= fields; ++f) {
      char field[33] = {};
      CGNS_ENUMT(DataType_t) type;
      check(cgns().cg_field_info(fn, base, zone.index, solution, f, &type, field), where);
      names.push_back(field);
    }
    const Range& range = at_cells ? zone.cells : zone.vertices;
    for (const VariableGroup& g : group_vector_variables(names)) {
      MeshArray a{g.name, g.components, {}};
      for (int c = 0; c < g.components; ++c) {
        const std::vector<double> v =
            per_kept_cell(zone, at_cells, read_array(zone, solution, names[size_t(g.first + c)], range), where);
        a.values.resize(v.size() * size_t(g.components));
        for (size_t i = 0; i < v.size(); ++i) a.values[i * size_t(g.components) + size_t(c)] = v[i];
      }
      (at_cells ? m.cell_data : m.point_data).push_back(std::move(a));
    }
  }

  // Cell values of an unstructured zone are its volume elements', in the order of their numbers
  // (boundary elements, and an NGON_n section's faces, may be numbered before them); the kept
  // cells' in their order.
  std::vector<double> per_kept_cell(const Zone& zone, bool at_cells, std::vector<double> v,
                                    const std::string& where) const {
    if (!at_cells || zone.structured) return v;
    input_check(zone.cell_value_index.size() == v.size(), file,
                where + ": " + std::to_string(v.size()) + " cell values for " +
                    std::to_string(zone.cell_value_index.size()) + " volume elements");
    std::vector<double> out;
    out.reserve(v.size());
    for (size_t i : zone.cell_value_index) out.push_back(v[i]);
    return out;
  }

  MeshData zone_step(const Zone& zone, size_t s) const {
    MeshData m = zone.topology;
    for (int solution : solutions_at(zone, s)) read_solution(zone, solution, m);
    return m;
  }

  // Every read the steps make, and nothing else (read_in_child_first).
  void read_all_values() const {
    for (size_t s = 0; s < times.size(); ++s)
      for (const Zone& z : zones) zone_step(z, s);
  }

  MeshData step(size_t s) const {
    input_check(s < times.size(), file, "no time step " + std::to_string(s));
    std::vector<MeshData> pieces;
    for (const Zone& z : zones) {
      pieces.push_back(zone_step(z, s));
      split_polyhedra(pieces.back(), z.faces, file, times.size() > 1 ? &z.polyhedra_split : nullptr);
    }
    MeshData m =
        pieces.size() == 1 ? std::move(pieces.front()) : join_pieces(std::move(pieces), file, MissingArrays::no_data);
    split_quadratic_cells(m, file, times.size() > 1 ? &quadratic_split : nullptr);
    check_mesh(m, file);
    return m;
  }

  std::string summary() const {
    const auto structured = std::count_if(zones.begin(), zones.end(), [](const Zone& z) { return z.structured; });
    std::string s = std::to_string(zones.size()) + (zones.size() == 1 ? " zone" : " zones");
    if (wanted.empty()) {
      if (structured) s += ", " + std::to_string(structured) + " structured";
    } else {  // the zones asked for: "2 zones read (block, structured; mixed)"
      std::vector<std::string> read;
      for (const Zone& z : zones) read.push_back(z.structured ? z.name + ", structured" : z.name);
      s += " read (" + joined(read, "; ") + ")";
    }
    const char* sep = ": ";
    std::map<std::string, uint64_t> counts = element_counts;
    for (size_t type = 0; type < elements_of_type.size(); ++type)
      if (elements_of_type[type]) counts[type_name(int(type))] = elements_of_type[type];
    for (const auto& [type, n] : counts) {
      s += sep + type + " x " + std::to_string(n);
      sep = ", ";
    }
    return s;
  }
};

CgnsFile::CgnsFile(const fs::path& file, const std::vector<std::string>& zones) : impl_(std::make_unique<Impl>()) {
  file_size_checked(file);  // a regular file (a FIFO would block every read below)
  impl_->wanted = zones;
  cgns();  // loaded here, not in the child below (read_in_child_first)
  read_in_child_first(file.string(), "CGNS", [&] {
    Impl first;
    first.wanted = zones;
    first.open(file);
    first.read_all_values();
  });
  impl_->open(file);
}
CgnsFile::~CgnsFile() = default;
size_t CgnsFile::step_count() const { return impl_->times.size(); }
double CgnsFile::step_time(size_t step) const { return impl_->times.at(step); }
MeshData CgnsFile::read_step(size_t step) { return impl_->step(step); }
std::string CgnsFile::summary() const { return impl_->summary(); }

#endif

}  // namespace vs
