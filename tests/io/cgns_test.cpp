// CGNS: files written from the standard's description (tests/data/cgns/make_cgns_files.py, whose
// node orders VTK's own CGNS reader confirms) read as the .vtu files VTK wrote of the same meshes
// and values: an unstructured zone of one MIXED section and a structured zone with a left-handed
// index space, over three time steps; quadratic sections with Vertex and CellCenter solutions;
// and bad files, written here with the CGNS library, refused with one line.
#include "volstream/io/cgns.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/io/vtu.h"
#include "volstream/umesh/from_mesh_data.h"
#include "volstream/umesh/mesh_pieces.h"

#ifdef VOLSTREAM_HAVE_CGNS
#include <cgnslib.h>
#endif

namespace vs {
namespace {
namespace fs = std::filesystem;

const fs::path kDir = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "cgns";

#define SKIP_WITHOUT_CGNS() \
  if (!cgns_supported()) GTEST_SKIP() << "built without CGNS"

TEST(Cgns, ZonesAndStepsAreTheVtuVtkWrote) {
  SKIP_WITHOUT_CGNS();
  CgnsFile cgns(kDir / "cgns_mixed.cgns");
  ASSERT_EQ(cgns.step_count(), 3u);
  EXPECT_EQ(cgns.step_time(1), 0.5);
  EXPECT_EQ(cgns.step_time(2), 1.25);
  EXPECT_EQ(cgns.summary(),
            "2 zones, 1 structured: HEXA_8 x 8, HEXA_8 (structured) x 24, PENTA_6 x 16, PYRA_5 x 48, TETRA_4 x 48");
  const MeshData step = cgns.read_step(1), vtu = read_vtu(kDir / "cgns_mixed_1.vtu");
  EXPECT_EQ(step.cell_count(), vtu.cell_count());
  EXPECT_EQ(step.points.size(), vtu.points.size());
  EXPECT_EQ(test::array_named(step.point_data, "Velocity").components, 3);
  test::expect_probes_alike(vtu, "g", step, "g");
  test::expect_probes_alike(vtu, "VelocityY", step, "Velocity_y");
  // Every element the right way round (make_umesh refuses elements turned against most others):
  // the structured zone's, whose k axis runs downwards, and the wedges.
  EXPECT_NO_THROW(make_umesh(step, mesh_transform(step), "cgns"));
}

TEST(Cgns, QuadraticSectionsAndCellCentredValues) {
  SKIP_WITHOUT_CGNS();
  CgnsFile cgns(kDir / "cgns_quadratic.cgns");
  EXPECT_EQ(cgns.step_count(), 1u);
  EXPECT_EQ(cgns.summary(), "1 zone: HEXA_20 x 2, HEXA_27 x 1, PENTA_15 x 1, PYRA_13 x 1, TETRA_10 x 1");
  const MeshData m = cgns.read_step(0), vtu = read_vtu(kDir / "cgns_quadratic.vtu");
  EXPECT_EQ(m.cell_count(), vtu.cell_count());
  EXPECT_EQ(m.connectivity, vtu.connectivity);
  EXPECT_EQ(test::array_named(m.cell_data, "cell_id").values, test::array_named(vtu.cell_data, "cell_id").values);
  test::expect_probes_alike(vtu, "g", m, "g");
}

// The zones asked for alone (--region): their cells and their solutions; the two read one by
// one and joined probe as the whole file; a zone the base lacks, one line listing its zones.
TEST(Cgns, ZonesAskedForAreTheWholeFilesZones) {
  SKIP_WITHOUT_CGNS();
  const fs::path file = kDir / "cgns_mixed.cgns";
  CgnsFile whole(file), block(file, {"block"}), mixed(file, {"mixed"}), both(file, {"mixed", "block"});
  EXPECT_EQ(mixed.summary(), "1 zone read (mixed): HEXA_8 x 8, PENTA_6 x 16, PYRA_5 x 48, TETRA_4 x 48");
  EXPECT_EQ(block.summary(), "1 zone read (block, structured): HEXA_8 (structured) x 24");
  EXPECT_EQ(both.summary(),
            "2 zones read (block, structured; mixed): HEXA_8 x 8, HEXA_8 (structured) x 24, PENTA_6 x 16, PYRA_5 x 48, "
            "TETRA_4 x 48");
  ASSERT_EQ(mixed.step_count(), 3u);
  const MeshData block_step = block.read_step(2), mixed_step = mixed.read_step(2), whole_step = whole.read_step(2);
  EXPECT_EQ(block_step.cell_count(), 24u);
  EXPECT_EQ(mixed_step.cell_count(), 120u);
  EXPECT_EQ(both.read_step(2).cell_count(), whole_step.cell_count());
  const MeshData joined = join_pieces({block_step, mixed_step}, "zones", MissingArrays::no_data);
  test::expect_probes_alike(whole_step, "g", joined, "g");
  test::expect_probes_alike(whole_step, "Velocity", both.read_step(2), "Velocity");
  EXPECT_NE(test::input_error_line([&] {
              CgnsFile f(file, {"mixed", "fluid"});
            }).find("no zone 'fluid' in this file's base Base (its zones: block, mixed)"),
            std::string::npos);
  EXPECT_EQ(open_mesh_files({file}, {}, {"block"})->read_step(0).cell_count(), 24u);
}

// A polyhedral zone (NGON_n faces in two sections, after the NFACE_n cells in the file but numbered
// before them) reads as the same polyhedra of VTK's file, split the same way, with the same
// values; the cell values by the cells' rank among the volume elements, not by their numbers.
TEST(Cgns, PolyhedralZoneIsTheVtuVtkWrote) {
  SKIP_WITHOUT_CGNS();
  CgnsFile cgns(kDir / "cgns_polyhedra.cgns");
  EXPECT_EQ(cgns.summary(), "1 zone: NFACE_n x 11");
  const MeshData m = cgns.read_step(0), vtu = read_vtu(kDir / ".." / "vtu" / "vtk_polyhedra.vtu");
  EXPECT_EQ(m.cell_count(), vtu.cell_count());
  EXPECT_EQ(m.points.size(), vtu.points.size());
  EXPECT_EQ(m.cell_types, vtu.cell_types);
  EXPECT_EQ(test::array_named(m.cell_data, "cell_id").values, test::array_named(vtu.cell_data, "cell_id").values);
  test::expect_probes_alike(vtu, "g", m, "g");
  test::expect_probes_alike(vtu, "f", m, "f");
}

// The same mesh with no NFACE_n section, its cells given by the faces' ParentElements (numbered
// after the faces), reads as the NFACE_n file does: the same cells, values and probes.
TEST(Cgns, CellsOfParentElementsAreTheNfaceCells) {
  SKIP_WITHOUT_CGNS();
  CgnsFile cgns(kDir / "cgns_ngon_parents.cgns"), nface(kDir / "cgns_polyhedra.cgns");
  EXPECT_EQ(cgns.summary(), "1 zone: polyhedra (NGON_n ParentElements) x 11");
  const MeshData m = cgns.read_step(0), reference = nface.read_step(0);
  EXPECT_EQ(m.points.size(), reference.points.size());
  // A cell's faces come in another order (the faces', not its NFACE_n list's), so its pieces do:
  // the same pieces per cell, cells in the same order.
  const auto pieces_per_cell = [](const MeshData& mesh) {
    std::vector<std::pair<double, int>> pieces;
    const std::vector<double>& cell_id = test::array_named(mesh.cell_data, "cell_id").values;
    for (uint64_t c = 0; c < mesh.cell_count(); ++c) pieces.emplace_back(cell_id[c], mesh.cell_types[c]);
    EXPECT_TRUE(std::is_sorted(cell_id.begin(), cell_id.end()));
    std::sort(pieces.begin(), pieces.end());
    return pieces;
  };
  EXPECT_EQ(pieces_per_cell(m), pieces_per_cell(reference));
  test::expect_probes_alike(reference, "g", m, "g");
  test::expect_probes_alike(reference, "f", m, "f");
}

#ifdef VOLSTREAM_HAVE_CGNS
// A small CGNS file written here: one unstructured zone of the unit cube's 8 nodes in a base of
// `cell_dim`, with one section of `type` holding `elements`.
struct BadFile {
  int cell_dim = 3;
  CGNS_ENUMT(ElementType_t) type = CGNS_ENUMV(HEXA_8);
  std::vector<cgsize_t> elements = {1, 2, 3, 4, 5, 6, 7, 8};
  std::vector<cgsize_t> offsets{};  // for NGON_n, NFACE_n
  std::vector<cgsize_t> parents{};  // NGON_n's ParentElements: the left cells, then the right
  cgsize_t zone_cells = 1;
  bool cell_values = false;  // a CellCenter solution of zone_cells values
};

fs::path write_cgns(const BadFile& b, const std::string& name) {
  const fs::path path = test::scratch_dir("cgns") / name;
  int fn = 0, base = 0, zone = 0, section = 0, coord = 0;
  auto ok = [](int status) { ASSERT_EQ(status, CG_OK) << cg_get_error(); };
  ok(cg_open(path.c_str(), CG_MODE_WRITE, &fn));
  ok(cg_base_write(fn, "Base", b.cell_dim, 3, &base));
  cgsize_t size[3] = {8, b.zone_cells, 0};
  ok(cg_zone_write(fn, base, "cube", size, CGNS_ENUMV(Unstructured), &zone));
  const double cube[3][8] = {{0, 1, 1, 0, 0, 1, 1, 0}, {0, 0, 1, 1, 0, 0, 1, 1}, {0, 0, 0, 0, 1, 1, 1, 1}};
  const char* names[] = {"CoordinateX", "CoordinateY", "CoordinateZ"};
  for (int a = 0; a < 3; ++a) ok(cg_coord_write(fn, base, zone, CGNS_ENUMV(RealDouble), names[a], cube[a], &coord));
  if (b.offsets.empty())
    ok(cg_section_write(fn, base, zone, "cells", b.type, 1, 1, 0, b.elements.data(), &section));
  else
    ok(cg_poly_section_write(fn, base, zone, "cells", b.type, 1, 1, 0, b.elements.data(), b.offsets.data(), &section));
  if (!b.parents.empty()) {
    const cgsize_t dimensions[2] = {cgsize_t(b.parents.size() / 2), 2};
    ok(cg_goto(fn, base, "Zone_t", zone, "Elements_t", section, "end"));
    ok(cg_array_write("ParentElements", sizeof(cgsize_t) == 8 ? CGNS_ENUMV(LongInteger) : CGNS_ENUMV(Integer), 2,
                      dimensions, b.parents.data()));
  }
  if (b.cell_values) {
    int solution = 0, field = 0;
    const std::vector<double> values(size_t(b.zone_cells), 1.0);
    ok(cg_sol_write(fn, base, zone, "values", CGNS_ENUMV(CellCenter), &solution));
    ok(cg_field_write(fn, base, zone, solution, CGNS_ENUMV(RealDouble), "v", values.data(), &field));
  }
  ok(cg_close(fn));
  return path;
}

std::string refusal(const fs::path& file) {
  try {
    CgnsFile cgns(file);
    const MeshData m = cgns.read_step(0);
    make_umesh(m, mesh_transform(m), file.string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "(read)";
}

TEST(Cgns, BadFilesAreRefusedWithOneLine) {
  EXPECT_EQ(refusal(write_cgns({}, "good.cgns")), "(read)");  // the cube, no solution: a mesh alone
  EXPECT_EQ(refusal(write_cgns({.cell_dim = 2}, "flat.cgns")),
            "no base of cell dimension 3: volstream renders volumes");
  BadFile out_of_range;
  out_of_range.elements.back() = 9;
  EXPECT_EQ(refusal(write_cgns(out_of_range, "range.cgns")),
            "zone cube, section cells, element 1: node 9 out of range 1..8");
  EXPECT_EQ(refusal(write_cgns({.type = CGNS_ENUMV(NGON_n), .elements = {1, 2, 3, 4}, .offsets = {0, 4}}, "ngon.cgns")),
            "zone cube: NGON_n faces without an NFACE_n section or the faces' ParentElements");
  const auto face_of = [](std::vector<cgsize_t> parents) {
    return BadFile{.type = CGNS_ENUMV(NGON_n), .elements = {1, 2, 3, 4}, .offsets = {0, 4}, .parents = parents};
  };
  EXPECT_EQ(refusal(write_cgns(face_of({1, 1}), "both_sides.cgns")), "zone cube: face 1 has one cell on both sides");
  EXPECT_EQ(refusal(write_cgns(face_of({1, -2}), "negative.cgns")), "zone cube: ParentElements name cell -2");
  EXPECT_EQ(refusal(write_cgns(face_of({1, 2}), "two_cells.cgns")),
            "zone cube: the faces' ParentElements name 2 cells, the zone has 1");
  EXPECT_NE(refusal(write_cgns(face_of({1, 0, 0, 0}), "parents_size.cgns")), "(read)");  // by the library
  EXPECT_NE(refusal(write_cgns(face_of({2, 0}), "one_face.cgns")), "(read)");            // a cell of one face
  EXPECT_EQ(
      refusal(write_cgns({.type = CGNS_ENUMV(NFACE_n), .elements = {5, 6, 7, 8}, .offsets = {0, 4}}, "nface.cgns")),
      "zone cube, section cells, cell 1: face 5 is in no NGON_n section");
  EXPECT_EQ(refusal(write_cgns({.zone_cells = 2, .cell_values = true}, "values.cgns")),
            "zone cube, solution values: 2 cell values for 1 volume elements");
  EXPECT_EQ(refusal(write_cgns({.cell_values = true}, "one_value.cgns")), "(read)");
  EXPECT_EQ(refusal(write_cgns({.type = CGNS_ENUMV(TETRA_16), .elements = std::vector<cgsize_t>(16, 1)}, "tet16.cgns")),
            "zone cube, section cells: unsupported element type TETRA_16 (TETRA_4/10, PYRA_5/13, PENTA_6/15, "
            "HEXA_8/20/27 are read)");
  EXPECT_EQ(refusal(write_cgns({.type = CGNS_ENUMV(QUAD_4), .elements = {1, 2, 3, 4}}, "faces.cgns")),
            "zone cube: no volume elements");

  // A file cut short, and one that is not CGNS: refused, whichever part of the library notices.
  const fs::path whole = kDir / "cgns_mixed.cgns", cut = test::scratch_dir("cgns") / "cut.cgns";
  std::ifstream in(whole, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (size_t keep : {size_t(100), size_t(5000), bytes.size() / 2, bytes.size() - 100}) {
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(keep));
    EXPECT_NE(refusal(cut), "(read)") << keep;
  }
  const fs::path text = test::scratch_dir("cgns") / "text.cgns";
  std::ofstream(text) << "not cgns\n";
  EXPECT_EQ(refusal(text).substr(0, 16), "not a CGNS file:");
}
#endif

}  // namespace
}  // namespace vs
