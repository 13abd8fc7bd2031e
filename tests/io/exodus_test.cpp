// Exodus II: files written from the format's description (tests/data/exodus/make_exodus_files.py,
// whose node orders VTK's own Exodus reader confirms) read as the .vtu files VTK wrote of the
// same meshes and values; every layout (64-bit offset, classic with the old one-variable
// layouts, NetCDF-4 compressed); the steps' times; and bad files, written here with the NetCDF
// library, refused with one line.
#include "volstream/io/exodus.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/io/vtu.h"
#include "volstream/umesh/from_mesh_data.h"

#ifdef VOLSTREAM_HAVE_NETCDF
#include <netcdf.h>
#endif

namespace vs {
namespace {
namespace fs = std::filesystem;

const fs::path kDir = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "exodus";

#define SKIP_WITHOUT_NETCDF() \
  if (!exodus_supported()) GTEST_SKIP() << "built without NetCDF"

void expect_near(double a, double b, const std::string& what) { EXPECT_NEAR(a, b, 1e-6 * (1 + std::fabs(b))) << what; }

// The Exodus variable `name` of `exo` (a vector's component NAME_x as component 0 of NAME)
// against the .vtu's array of that name.
void expect_array(const std::vector<MeshArray>& exo, const std::vector<MeshArray>& vtu, const std::string& name) {
  const MeshArray& want = test::array_named(vtu, name);
  const bool component = name.size() > 2 && name[name.size() - 2] == '_';
  const MeshArray& got = test::array_named(exo, component ? name.substr(0, name.size() - 2) : name);
  const size_t stride = size_t(got.components), c = component ? size_t(name.back() - 'x') : 0;
  ASSERT_EQ(got.values.size(), want.values.size() * stride) << name;
  for (size_t i = 0; i < want.values.size(); ++i) expect_near(got.values[i * stride + c], want.values[i], name);
}

// The same points (to the .vtu's printed precision), cells and arrays.
void expect_same_mesh(const MeshData& exo, const MeshData& vtu, const std::vector<std::string>& point_arrays,
                      const std::vector<std::string>& cell_arrays) {
  ASSERT_EQ(exo.points.size(), vtu.points.size());
  for (size_t i = 0; i < vtu.points.size(); ++i)
    for (int a = 0; a < 3; ++a) expect_near(exo.points[i][a], vtu.points[i][a], "point " + std::to_string(i));
  EXPECT_EQ(exo.cell_types, vtu.cell_types);
  EXPECT_EQ(exo.cell_offsets, vtu.cell_offsets);
  EXPECT_EQ(exo.connectivity, vtu.connectivity);
  for (const std::string& n : point_arrays) expect_array(exo.point_data, vtu.point_data, n);
  for (const std::string& n : cell_arrays) expect_array(exo.cell_data, vtu.cell_data, n);
}

TEST(Exodus, MixedElementsAndStepsAreTheVtusVtkWrote) {
  SKIP_WITHOUT_NETCDF();
  ExodusFile exo(kDir / "exodus_mixed.exo");
  ASSERT_EQ(exo.step_count(), 3u);
  EXPECT_EQ(exo.step_time(0), 0.0);
  EXPECT_EQ(exo.step_time(1), 0.5);
  EXPECT_EQ(exo.step_time(2), 1.25);
  EXPECT_EQ(exo.summary(), "64-bit offset: HEX8 x 8, PYRAMID5 x 48, TETRA x 48, WEDGE6 x 16");
  const MeshData step = exo.read_step(1);
  expect_same_mesh(step, read_vtu(kDir / "exodus_mixed_1.vtu"), {"f", "g", "vel_x", "vel_y", "vel_z"},
                   {"cell_id", "pressure"});
  EXPECT_EQ(test::array_named(step.point_data, "vel").components, 3);
  // Every element the right way round (make_umesh refuses elements turned against most others):
  // the 16 wedges too, whose first triangle Exodus turns towards the second.
  EXPECT_NO_THROW(make_umesh(step, mesh_transform(step), "exodus"));
}

TEST(Exodus, OldOneVariableLayoutsReadAsTheCurrentOnes) {
  SKIP_WITHOUT_NETCDF();
  ExodusFile old(kDir / "exodus_old.exo");
  EXPECT_EQ(old.summary().substr(0, 8), "classic:");
  ASSERT_EQ(old.step_count(), 1u);
  const MeshData a = old.read_step(0), b = ExodusFile(kDir / "exodus_mixed.exo").read_step(0);
  EXPECT_EQ(a.points.size(), b.points.size());
  for (size_t i = 0; i < a.points.size(); ++i) EXPECT_EQ(a.points[i], b.points[i]) << i;
  EXPECT_EQ(a.connectivity, b.connectivity);
  for (const char* n : {"f", "g", "vel"})
    EXPECT_EQ(test::array_named(a.point_data, n).values, test::array_named(b.point_data, n).values) << n;
}

// A parallel run's two rank files (every other element of each block on each, on their own
// nodes), from either of them: joined into the whole file's mesh, the shared nodes welded.
TEST(Exodus, RankFilesJoinIntoTheWholeMesh) {
  SKIP_WITHOUT_NETCDF();
  const auto ranks = open_mesh_files({kDir / "exodus_mixed.exo.2.1"});
  EXPECT_EQ(ranks->description(), "Exodus II exodus_mixed.exo.2.0 (2 rank files, 64-bit offset; 3 steps)");
  ASSERT_EQ(ranks->step_count(), 3);
  EXPECT_EQ(ranks->step_time(2), 1.25);
  const MeshData joined = ranks->read_step(1), whole = ExodusFile(kDir / "exodus_mixed.exo").read_step(1);
  EXPECT_EQ(joined.cell_count(), whole.cell_count());
  EXPECT_EQ(joined.points.size(), whole.points.size()) << "every shared node welded";
  test::expect_probes_alike(whole, "g", joined, "g");
  test::expect_probes_alike(whole, "pressure", joined, "pressure");
  EXPECT_THROW(open_mesh_files({kDir / "exodus_mixed.exo.2.1", kDir / "exodus_mixed.exo"}), UsageError);
}

// NetCDF-4 (HDF5, zlib): HEX20, HEX27, TETRA10, WEDGE15 and PYRAMID13 in Exodus's node orders,
// split as the .vtu's quadratic cells are.
TEST(Exodus, QuadraticElementsSplitAsTheVtusCells) {
  SKIP_WITHOUT_NETCDF();
  ExodusFile exo(kDir / "exodus_quadratic.exo");
  EXPECT_EQ(exo.summary(), "NetCDF-4: HEX20 x 2, HEX27 x 1, PYRAMID13 x 1, TETRA10 x 1, WEDGE15 x 1");
  const MeshData m = exo.read_step(0);
  expect_same_mesh(m, read_vtu(kDir / "exodus_quadratic.vtu"), {"f", "g"}, {"cell_id"});
  EXPECT_NO_THROW(make_umesh(m, mesh_transform(m), "exodus"));
}

// The element blocks asked for alone (by id): their elements, the nodes they use with the same
// values, the whole file's element values; a rank set the same; a block the file lacks, or only
// surface blocks, one line.
TEST(Exodus, ElementBlocksAskedForAreTheWholeFilesElements) {
  SKIP_WITHOUT_NETCDF();
  ExodusFile whole_file(kDir / "exodus_mixed.exo"), hexes_file(kDir / "exodus_mixed.exo", {"20"});
  EXPECT_EQ(hexes_file.summary(), "64-bit offset: HEX8 x 8; blocks read: 20");
  const MeshData whole = whole_file.read_step(2), hexes = hexes_file.read_step(2);
  ASSERT_EQ(hexes.cell_count(), 8u);
  EXPECT_EQ(hexes.points.size(), 27u);  // the 2x2x2 hexes' 3x3x3 nodes
  const MeshArray& g = test::array_named(hexes.point_data, "g");
  const MeshArray& whole_g = test::array_named(whole.point_data, "g");
  for (uint64_t e = 0; e < 8; ++e) {
    const uint64_t w = 48 + e;  // after block 10's 48 tets
    ASSERT_EQ(hexes.cell_types[e], whole.cell_types[w]);
    for (uint64_t k = 0; k < 8; ++k) {
      const uint64_t a = hexes.connectivity[hexes.cell_offsets[e] + k],
                     b = whole.connectivity[whole.cell_offsets[w] + k];
      EXPECT_EQ(hexes.points[a], whole.points[b]);
      EXPECT_EQ(g.values[a], whole_g.values[b]);
    }
    EXPECT_EQ(test::array_named(hexes.cell_data, "pressure").values[e],
              test::array_named(whole.cell_data, "pressure").values[w]);
  }
  const auto ranks = open_mesh_files({kDir / "exodus_mixed.exo.2.0"}, {}, {"20", "30"});
  const auto one = open_mesh_files({kDir / "exodus_mixed.exo"}, {}, {"30", "20"});
  test::expect_probes_alike(ranks->read_step(1), "g", one->read_step(1), "g");
  EXPECT_NE(test::input_error_line([&] {
              ExodusFile f(kDir / "exodus_mixed.exo", {"20", "60"});
            }).find("no element block '60' in this file (its blocks: 10, 20, 30, 40, 50)"),
            std::string::npos);
  EXPECT_NE(test::input_error_line([&] {
              open_mesh_files({kDir / "exodus_mixed.exo"}, {}, {"50"})->read_step(0);
            }).find("no volume elements in the parts asked for"),
            std::string::npos);
}

#ifdef VOLSTREAM_HAVE_NETCDF
// An element variable without values on one block of several (a material's variable) is NaN, no
// data, on that block's elements alone, and the summary says where.
TEST(Exodus, ElementVariableMissingOnABlockIsNoDataThere) {
  const fs::path copy = test::scratch_dir("exodus") / "partial_blocks.exo";
  fs::copy_file(kDir / "exodus_mixed.exo", copy, fs::copy_options::overwrite_existing);
  int nc = 0, var = 0;
  ASSERT_EQ(nc_open(copy.c_str(), NC_WRITE, &nc), NC_NOERR);
  ASSERT_EQ(nc_redef(nc), NC_NOERR);
  ASSERT_EQ(nc_inq_varid(nc, "vals_elem_var2eb2", &var), NC_NOERR);  // pressure on block 2 (id 20)
  ASSERT_EQ(nc_rename_var(nc, var, "not_a_value_var"), NC_NOERR);
  ASSERT_EQ(nc_close(nc), NC_NOERR);
  ExodusFile partial(copy);
  EXPECT_NE(partial.summary().find("element variable pressure no data (NaN) on element block 20"), std::string::npos)
      << partial.summary();
  const MeshData a = partial.read_step(1), b = ExodusFile(kDir / "exodus_mixed.exo").read_step(1);
  const MeshArray &p = test::array_named(a.cell_data, "pressure"), &q = test::array_named(b.cell_data, "pressure");
  ASSERT_EQ(p.values.size(), q.values.size());
  for (size_t e = 0; e < p.values.size(); ++e) {
    const bool block_2 = e >= 48 && e < 56;  // block 1's 48 tets, then block 2's 8 hexes
    if (block_2)
      EXPECT_TRUE(std::isnan(p.values[e])) << e;
    else
      EXPECT_EQ(p.values[e], q.values[e]) << e;
  }
  EXPECT_EQ(test::array_named(a.cell_data, "cell_id").values, test::array_named(b.cell_data, "cell_id").values);
}

// A small Exodus file written here: one unit cube of 8 nodes and one block of `type` whose
// elements are `connect` (1-based, `nodes` per element); `dims` spatial dimensions; an element
// variable over the block when `element_variable`.
struct BadFile {
  int dims = 3;
  std::string type = "HEX8";
  int nodes = 8;
  std::vector<int> connect = {1, 2, 3, 4, 5, 6, 7, 8};
  bool element_variable_names = false;  // name one element variable but write no values
};

fs::path write_exodus(const BadFile& b, const std::string& name) {
  const fs::path path = test::scratch_dir("exodus") / name;
  int nc = 0, d[8], v = 0;
  auto ok = [](int status) { ASSERT_EQ(status, NC_NOERR) << nc_strerror(status); };
  ok(nc_create(path.c_str(), NC_CLOBBER | NC_64BIT_OFFSET, &nc));
  ok(nc_def_dim(nc, "num_dim", size_t(b.dims), &d[0]));
  ok(nc_def_dim(nc, "num_nodes", 8, &d[1]));
  ok(nc_def_dim(nc, "num_el_blk", 1, &d[2]));
  ok(nc_def_dim(nc, "num_el_in_blk1", b.connect.size() / size_t(b.nodes), &d[3]));
  ok(nc_def_dim(nc, "num_nod_per_el1", size_t(b.nodes), &d[4]));
  ok(nc_def_dim(nc, "time_step", NC_UNLIMITED, &d[5]));
  int coord[3];
  for (int a = 0; a < 3; ++a)
    ok(nc_def_var(nc, std::string(1, "xyz"[a]).insert(0, "coord").c_str(), NC_DOUBLE, 1, &d[1], &coord[a]));
  int connect_dims[2] = {d[3], d[4]};
  ok(nc_def_var(nc, "connect1", NC_INT, 2, connect_dims, &v));
  ok(nc_put_att_text(nc, v, "elem_type", b.type.size(), b.type.c_str()));
  int time = 0;
  ok(nc_def_var(nc, "time_whole", NC_DOUBLE, 1, &d[5], &time));
  if (b.element_variable_names) {
    ok(nc_def_dim(nc, "num_elem_var", 1, &d[6]));
    ok(nc_def_dim(nc, "len_name", 33, &d[7]));
    int names_dims[2] = {d[6], d[7]}, names = 0;
    ok(nc_def_var(nc, "name_elem_var", NC_CHAR, 2, names_dims, &names));
    ok(nc_enddef(nc));
    char row[33] = "pressure";
    ok(nc_put_var_text(nc, names, row));
  } else {
    ok(nc_enddef(nc));
  }
  const double cube[3][8] = {{0, 1, 1, 0, 0, 1, 1, 0}, {0, 0, 1, 1, 0, 0, 1, 1}, {0, 0, 0, 0, 1, 1, 1, 1}};
  for (int a = 0; a < 3; ++a) ok(nc_put_var_double(nc, coord[a], cube[a]));
  ok(nc_put_var_int(nc, v, b.connect.data()));
  const size_t start = 0, count = 1;
  const double t = 0;
  ok(nc_put_vara_double(nc, time, &start, &count, &t));
  ok(nc_close(nc));
  return path;
}

std::string refusal(const fs::path& file) {
  try {
    ExodusFile exo(file);
    const MeshData m = exo.read_step(0);
    make_umesh(m, mesh_transform(m), file.string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "(read)";
}

TEST(Exodus, BadFilesAreRefusedWithOneLine) {
  EXPECT_EQ(refusal(write_exodus({}, "good.exo")), "(read)");  // the cube, no variables: a mesh alone

  EXPECT_EQ(refusal(write_exodus({.dims = 2}, "flat.exo")), "a 2D Exodus mesh: volstream renders volumes (num_dim 3)");
  BadFile out_of_range;
  out_of_range.connect.back() = 9;
  EXPECT_EQ(refusal(write_exodus(out_of_range, "range.exo")), "element block 1, element 1: node 9 out of range 1..8");
  out_of_range.connect.back() = 0;
  EXPECT_EQ(refusal(write_exodus(out_of_range, "zero.exo")), "element block 1, element 1: node 0 out of range 1..8");
  EXPECT_EQ(refusal(write_exodus({.type = "NFACED", .nodes = 8}, "nfaced.exo")),
            "element block 1: unsupported element type NFACED with 8 nodes (TETRA4/10, HEX8/20/27, WEDGE6/15, "
            "PYRAMID5/13 are read)");
  EXPECT_EQ(refusal(write_exodus({.type = "TETRA", .nodes = 8}, "tet8.exo")).substr(0, 52),
            "element block 1: unsupported element type TETRA with");
  EXPECT_EQ(refusal(write_exodus({.type = "SHELL4", .nodes = 4, .connect = {1, 2, 3, 4}}, "shell.exo")),
            "no volume elements (only surface, line or point element blocks)");
  // An element variable without values on its only block is left out, and the summary says so.
  ExodusFile partial(write_exodus({.element_variable_names = true}, "partial.exo"));
  EXPECT_EQ(partial.summary(),
            "64-bit offset: HEX8 x 1; element variable pressure left out (no values on element block 1)");
  EXPECT_TRUE(partial.read_step(0).cell_data.empty());

  // The NetCDF library reads a classic file cut short as zeros: every cut is refused here.
  const fs::path whole = kDir / "exodus_mixed.exo", cut = test::scratch_dir("exodus") / "cut.exo";
  std::ifstream in(whole, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (size_t keep : {size_t(100), size_t(2000), size_t(9000), bytes.size() - 8}) {
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(keep));
    const std::string why = refusal(cut);
    const bool in_header = keep < 9000;  // there the library may refuse it first
    EXPECT_TRUE(in_header ? why.starts_with("truncated in its NetCDF header (") || why.starts_with("not a NetCDF file")
                          : why.starts_with("truncated: its variables need 27404 bytes"))
        << keep << ": " << why;
  }

  // One byte changed in exodus_quadratic.exo (found by fuzzing): HDF5 frees an uninitialised
  // pointer opening it. Read in a child process first, it is refused either way: by the child's
  // fall (under a sanitizer) or by the error HDF5 reports.
  const std::string damaged = refusal(kDir / "damaged_hdf5.exo");
  EXPECT_TRUE(damaged.starts_with("a damaged NetCDF-4 file: the HDF5 library failed reading it") ||
              damaged == "not a NetCDF file (Exodus II files are): NetCDF: HDF error")
      << damaged;

  const fs::path directory = test::scratch_dir("exodus") / "directory.exo";
  fs::create_directories(directory);
  EXPECT_NE(refusal(directory), "(read)");

  const fs::path text = test::scratch_dir("exodus") / "text.exo";
  std::ofstream(text) << "not netcdf\n";
  EXPECT_EQ(refusal(text).substr(0, 39), "not a NetCDF file (Exodus II files are)");
}
#endif

}  // namespace
}  // namespace vs
