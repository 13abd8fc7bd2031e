// Gmsh MSH: files Gmsh itself wrote (tests/data/gmsh/make_gmsh_files.py) in MSH 4.1 and 2.2,
// ascii and binary, read alike; each element type's node order checked against Gmsh's own basis
// functions at points inside its elements (the FILE_probes.txt Gmsh wrote); views as point and
// cell data, their time steps; and damaged files (cut short anywhere, a missing node, an unknown
// version, huge counts) refused with one line.
#include "volstream/io/gmsh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "test_util.h"
#include "volstream/core/error.h"
#include "volstream/io/mesh_convert.h"
#include "volstream/render/integrators/umesh_renderer.h"
#include "volstream/umesh/from_mesh_data.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

const fs::path kDir = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "data" / "gmsh";
const char* const kTetFiles[] = {"gmsh_tets_41a.msh", "gmsh_tets_41b.msh", "gmsh_tets_22a.msh", "gmsh_tets_22b.msh"};

fs::path write_scratch(const std::string& bytes, const std::string& name) {
  const fs::path path = test::scratch_dir("gmsh") / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// The file's refusal, "(read)" if every step reads and makes a mesh the renderer takes.
std::string refusal(const fs::path& file) {
  try {
    GmshFile msh(file);
    for (size_t s = 0; s < msh.step_count(); ++s) {
      const MeshData m = msh.read_step(s);
      make_umesh(m, mesh_transform(m), file.string());
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "(read)";
}

// The refusal of the file read with physical `groups` asked for.
std::string refusal_with(const fs::path& file, const std::vector<std::string>& groups) {
  try {
    GmshFile(file, groups).read_step(0);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(read)";
}

// The views make_gmsh_files.py wrote, against the formulas it wrote them from: f, vel, pressure
// (element tag / 2 + step) and cell_id (element tag, given once) exactly at every point and cell.
void expect_views_of_step(const MeshData& m, int step) {
  const MeshArray& f = test::array_named(m.point_data, "f");
  const MeshArray& vel = test::array_named(m.point_data, "vel");
  ASSERT_EQ(vel.components, 3);
  for (size_t i = 0; i < m.points.size(); ++i) {
    const vec3d p = m.points[i];
    EXPECT_NEAR(f.values[i], (1 + step) * (p.x + 2 * p.y + 3 * p.z), 1e-12) << "point " << i;
    EXPECT_NEAR(vel.values[3 * i], p.y * (1 + step), 1e-12);
    EXPECT_NEAR(vel.values[3 * i + 1], -p.x, 1e-12);
    EXPECT_NEAR(vel.values[3 * i + 2], 0.5 * step, 1e-12);
  }
  const MeshArray& pressure = test::array_named(m.cell_data, "pressure");
  const MeshArray& cell_id = test::array_named(m.cell_data, "cell_id");
  for (size_t c = 0; c < m.cell_count(); ++c) EXPECT_EQ(pressure.values[c], cell_id.values[c] / 2 + step) << c;
}

TEST(Gmsh, FourEncodingsReadAlikeWithTheirSteps) {
  const MeshData reference = GmshFile(kDir / kTetFiles[0]).read_step(1);
  for (const char* name : kTetFiles) {
    SCOPED_TRACE(name);
    GmshFile msh(kDir / name);
    ASSERT_EQ(msh.step_count(), 3u);
    EXPECT_EQ(msh.step_time(0), 0.0);
    EXPECT_EQ(msh.step_time(1), 0.5);
    EXPECT_EQ(msh.step_time(2), 1.25);
    const std::string version = std::string(name).substr(10, 1) + "." + std::string(name).substr(11, 1);
    const std::string encoding = name[12] == 'a' ? "ascii" : "binary";
    EXPECT_EQ(msh.summary(), "MSH " + version + " " + encoding + ": tet4 x 261");
    for (int step = 0; step < 3; ++step) {
      const MeshData m = msh.read_step(size_t(step));
      EXPECT_EQ(m.points.size(), 102u);
      EXPECT_EQ(m.cell_count(), 261u);
      expect_views_of_step(m, step);
    }
    const MeshData m = msh.read_step(1);
    EXPECT_NO_THROW(make_umesh(m, mesh_transform(m), name));
    for (const char* field : {"f", "g", "vel", "pressure", "cell_id"})
      test::expect_probes_alike(reference, field, m, field);
  }
}

struct Probe {
  int type;
  vec3d at;
  double g;
};

std::vector<Probe> probes_of(const std::string& stem) {
  std::ifstream in(kDir / (stem + "_probes.txt"));
  std::vector<Probe> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    Probe p;
    fields >> p.type >> p.at.x >> p.at.y >> p.at.z >> p.g;
    out.push_back(p);
  }
  return out;
}

// The view g probed in volstream's mesh at the points Gmsh evaluated it at, per Gmsh element
// type: the probes of each type that differ (or fall outside every element). The renderer samples
// float32 values at float32 points, so agreement is to float precision, not double's.
std::map<int, int> g_mismatches(const std::string& stem, std::map<int, int>& probed) {
  const MeshData m = GmshFile(kDir / (stem + ".msh")).read_step(0);
  const WorldTransform xf = mesh_transform(m);
  const UMesh mesh = make_umesh(m, xf, stem);
  const UMeshRenderer renderer(mesh, xf);
  const std::vector<float> g = test::mesh_field(m, "g");
  const std::vector<Probe> probes = probes_of(stem);
  std::vector<vec3f> points;
  for (const Probe& p : probes) points.push_back(vec3f(xf.to_grid(p.at)));
  const std::vector<float> values = renderer.probe(g.data(), points);
  std::map<int, int> bad;
  for (size_t i = 0; i < probes.size(); ++i) {
    ++probed[probes[i].type];
    const bool alike = std::fabs(values[i] - probes[i].g) <= 2e-6 * (1 + std::fabs(probes[i].g));
    if (!alike) {
      ++bad[probes[i].type];
      ADD_FAILURE() << stem << ": type " << probes[i].type << " at (" << probes[i].at.x << ", " << probes[i].at.y
                    << ", " << probes[i].at.z << "): " << values[i] << ", Gmsh " << probes[i].g;
    }
  }
  return bad;
}

// Linear elements at random points inside them; quadratic ones (curved: their mid-edge nodes
// moved off the edges) inside the piece at each corner, where the split is exact (see the
// generator): a node put in another's place moves the pieces, and g's values with them.
TEST(Gmsh, NodeOrdersAgreeWithGmshsBasisFunctions) {
  std::map<int, int> probed;
  for (const char* stem : {"gmsh_tets", "gmsh_mixed", "gmsh_serendipity", "gmsh_quadratic"}) {
    SCOPED_TRACE(stem);
    EXPECT_TRUE(g_mismatches(stem == std::string("gmsh_tets") ? "gmsh_tets_41a" : stem, probed).empty());
  }
  // Every type read was probed.
  for (int type : {4, 5, 6, 7, 11, 12, 13, 17, 18, 19}) EXPECT_GT(probed[type], 10) << "type " << type;
}

// The sign of each linear cell's first face's normal (right-handed) against the way to its other
// corners: positive for VTK's tetra, hexahedron and pyramid, negative for its wedge (whose first
// triangle's normal points away from the second, as VTK's documentation, volstream's demo meshes
// and its Exodus, EnSight and CGNS readers have it; Gmsh's prism is the other way round). The
// renderer takes either orientation as long as a type's cells agree, so the probes alone cannot
// tell a prism read the wrong way round.
std::map<uint8_t, std::set<int>> orientation_signs(const MeshData& m) {
  std::map<uint8_t, std::set<int>> signs;
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    const uint64_t* v = m.connectivity.data() + m.cell_offsets[c];
    auto p = [&](int k) { return m.points[v[k]]; };
    const int n = cell_vertex_count(m.cell_types[c]);
    const int first_face = n == 4 || n == 6 ? 3 : 4;  // corners 0 .. first_face-1, then the others
    const vec3d normal = cross(p(1) - p(0), p(first_face - 1) - p(0));
    vec3d others(0.0);
    for (int k = first_face; k < n; ++k) others = others + p(k) * (1.0 / (n - first_face));
    const vec3d rest = others - p(0);
    signs[m.cell_types[c]].insert(dot(normal, rest) > 0 ? 1 : -1);
  }
  return signs;
}

TEST(Gmsh, CellsAreInVtksOrientation) {
  const std::map<uint8_t, std::set<int>> vtk = {{10, {1}}, {12, {1}}, {13, {-1}}, {14, {1}}};
  for (const char* name : {"gmsh_mixed.msh", "gmsh_serendipity.msh", "gmsh_quadratic.msh", "gmsh_tets_22b.msh"}) {
    const std::map<uint8_t, std::set<int>> signs = orientation_signs(GmshFile(kDir / name).read_step(0));
    for (const auto& [type, s] : signs) EXPECT_EQ(s, vtk.at(type)) << name << ": VTK type " << int(type);
  }
}

TEST(Gmsh, MixedAndQuadraticElements) {
  EXPECT_EQ(GmshFile(kDir / "gmsh_mixed.msh").summary(),
            "MSH 4.1 binary: hex8 x 8, prism6 x 28, pyramid5 x 4, tet4 x 137");
  EXPECT_EQ(GmshFile(kDir / "gmsh_serendipity.msh").summary(),
            "MSH 4.1 ascii: hex20 x 8, prism15 x 28, pyramid13 x 4, tet10 x 137");
  EXPECT_EQ(GmshFile(kDir / "gmsh_quadratic.msh").summary(), "MSH 2.2 binary: hex27 x 8, prism18 x 28");
  for (const char* name : {"gmsh_mixed.msh", "gmsh_serendipity.msh", "gmsh_quadratic.msh"})
    EXPECT_EQ(refusal(kDir / name), "(read)") << name;
  // One step (the views' step 0); cell_id on every piece of a split element.
  GmshFile quadratic(kDir / "gmsh_quadratic.msh");
  ASSERT_EQ(quadratic.step_count(), 1u);
  const MeshData m = quadratic.read_step(0);
  EXPECT_EQ(m.cell_count(), 8u * 8 + 28 * 8);
  EXPECT_EQ(test::array_named(m.cell_data, "cell_id").values.size(), m.cell_count());
  EXPECT_EQ(refusal(kDir / "gmsh_pyramid14.msh"),
            "volume element type 14 x 4 is not read (the 14-node pyramid: VTK has no such cell; the 13-node one, "
            "type 19, is read)");
}

TEST(Gmsh, ConvertsAsOneFileOrASeriesOfFiles) {
  const auto one = open_mesh_files({kDir / "gmsh_tets_41b.msh"});
  EXPECT_EQ(one->step_count(), 3);
  EXPECT_EQ(one->step_time(2), 1.25);
  EXPECT_EQ(one->description(), "Gmsh gmsh_tets_41b.msh (MSH 4.1 binary: tet4 x 261; 3 steps)");
  EXPECT_TRUE(is_mesh_file("a/B.MSH"));
  // Files of one step each are a series; a file of several steps is not a step of one.
  const auto two = open_mesh_files({kDir / "gmsh_mixed.msh", kDir / "gmsh_mixed.msh"});
  EXPECT_EQ(two->step_count(), 2);
  EXPECT_EQ(two->read_step(1).cell_count(), 177u);
  const auto bad = open_mesh_files({kDir / "gmsh_mixed.msh", kDir / "gmsh_tets_41a.msh"});
  EXPECT_THROW(bad->read_step(1), InputError);
}

// Physical groups of volumes (--region), as Gmsh's model holds them (gmsh_groups.txt: each
// group's element count and the sum of its elements' numbers, the view cell_id): by name or
// number, overlapping groups as their union, the nodes of the other elements dropped, f (linear)
// exact at every node kept; a partitioned file's groups through its partitions' entities. MSH
// 2.2 writes an element once per group holding it, under new numbers: read once, its view values
// found under any copy's number.
TEST(Gmsh, PhysicalGroupsAreThoseOfGmshsModel) {
  std::map<int64_t, std::pair<uint64_t, double>> groups;  // number -> (elements, sum of cell_id)
  std::istringstream table(test::file_bytes(kDir / "gmsh_groups.txt"));
  for (std::string line; std::getline(table, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    int64_t number = 0;
    uint64_t count = 0;
    double sum = 0;
    row >> number >> count >> sum;
    groups[number] = {count, sum};
  }
  ASSERT_EQ(groups.size(), 5u);
  const std::map<int64_t, std::string> names = {{7, "hex block"}, {8, "prisms"}, {9, "top"}, {11, "lower"}};
  const auto cell_id_sum = [](const MeshData& m) {
    double sum = 0;
    for (double v : test::array_named(m.cell_data, "cell_id").values) sum += v;
    return sum;
  };
  const auto expect_nodes_used_and_f_exact = [](const MeshData& m) {
    EXPECT_EQ(std::set<uint64_t>(m.connectivity.begin(), m.connectivity.end()).size(), m.points.size());
    const MeshArray& f = test::array_named(m.point_data, "f");
    for (size_t i = 0; i < m.points.size(); ++i)
      EXPECT_NEAR(f.values[i], m.points[i].x + 2 * m.points[i].y + 3 * m.points[i].z, 1e-12);
  };
  for (const char* name : {"gmsh_groups_41.msh", "gmsh_groups_41b.msh", "gmsh_groups_41p.msh", "gmsh_groups_22.msh"}) {
    SCOPED_TRACE(name);
    const MeshData whole = GmshFile(kDir / name).read_step(0);
    EXPECT_EQ(whole.cell_count(), 177u);
    EXPECT_EQ(cell_id_sum(whole), groups[7].second + groups[8].second + groups[9].second);
    for (const auto& [number, expected] : groups) {
      std::vector<std::string> keys = {std::to_string(number)};
      if (names.count(number)) keys.push_back(names.at(number));
      for (const std::string& key : keys) {
        SCOPED_TRACE(key);
        const MeshData m = GmshFile(kDir / name, {key}).read_step(0);
        EXPECT_EQ(m.cell_count(), expected.first);
        EXPECT_EQ(cell_id_sum(m), expected.second);
        expect_nodes_used_and_f_exact(m);
      }
    }
    const MeshData lower_and_hexes = GmshFile(kDir / name, {"lower", "hex block"}).read_step(0);
    EXPECT_EQ(lower_and_hexes.cell_count(), groups[11].first);
    EXPECT_NE(GmshFile(kDir / name, {"12", "hex block"}).summary().find("; physical groups read: 7 (hex block) 12"),
              std::string::npos);
    for (const char* missing : {"bottom", "13", "nope"})
      EXPECT_EQ(refusal_with(kDir / name, {missing}),
                std::string("no physical group '") + missing +
                    "' of volume elements in this file (its groups of volumes: 7 (hex block), 8 (prisms), 9 (top), "
                    "11 (lower), 12)");
  }
  EXPECT_EQ(GmshFile(kDir / "gmsh_groups_22.msh").summary(),
            "MSH 2.2 binary: hex8 x 8, prism6 x 28, pyramid5 x 4, tet4 x 137; 101 copies of elements in a second "
            "physical group read once");
  test::expect_probes_alike(GmshFile(kDir / "gmsh_groups_41.msh").read_step(0), "f",
                            GmshFile(kDir / "gmsh_groups_22.msh").read_step(0), "f");
  // A file without groups is refused. A series of .msh files reads the groups asked for at every
  // step; one with a .vtu step is refused.
  EXPECT_EQ(refusal_with(kDir / "gmsh_tets_22a.msh", {"1"}),
            "no physical group '1' of volume elements in this file (its groups of volumes: none)");
  const auto series = open_mesh_files({kDir / "gmsh_groups_41.msh", kDir / "gmsh_groups_22.msh"}, {}, {"prisms"});
  EXPECT_EQ(series->step_count(), 2);
  EXPECT_EQ(series->read_step(1).cell_count(), 28u);
  EXPECT_NE(series->description().find("(2 steps; physical groups prisms)"), std::string::npos)
      << series->description();
  EXPECT_THROW(
      open_mesh_files({kDir / "gmsh_groups_41.msh", kDir / "gmsh_groups_22.msh"}, {}, {"7", "absent"})->read_step(0),
      InputError);
  EXPECT_THROW(open_mesh_files({kDir / "gmsh_groups_41.msh", kDir / "../vtu/vtk_zlib.vtu"}, {}, {"7"}), UsageError);
  EXPECT_EQ(open_mesh_files({kDir / "gmsh_groups_41.msh"}, {}, {"prisms"})->read_step(0).cell_count(), 28u);
}

// Sections not read are skipped to their end line; $ElementNodeData views are left out, and the
// summary says so.
TEST(Gmsh, SectionsNotReadAreSkipped) {
  const std::string file = test::file_bytes(kDir / "gmsh_tets_22a.msh") +
                           "$Comments\n$Nodes inside another section\n$EndComments\n" +
                           "$ElementNodeData\n1\n\"stress\"\n1\n0.5\n3\n0\n1\n1\n1 4 1 2 3 4\n$EndElementNodeData\n";
  GmshFile msh(write_scratch(file, "extra.msh"));
  EXPECT_EQ(msh.summary(), "MSH 2.2 ascii: tet4 x 261; $ElementNodeData 'stress' left out");
  ASSERT_EQ(msh.step_count(), 3u);
  expect_views_of_step(msh.read_step(2), 2);
  EXPECT_EQ(refusal(write_scratch(test::file_bytes(kDir / "gmsh_tets_22a.msh") + "$Comments\nno end\n", "open.msh")),
            "truncated: no $EndComments after $Comments");
}

// Each of the four encodings cut short at 60 places: refused with one line, or (cut right after
// a section's end) read as the sections before.
TEST(Gmsh, FilesCutShortAreRefusedWithOneLine) {
  for (const char* name : kTetFiles) {
    const std::string full = test::file_bytes(kDir / name);
    int refused = 0;
    for (int k = 1; k < 60; ++k) {
      const size_t cut = full.size() * size_t(k) / 60;
      const std::string prefix = full.substr(0, cut);
      const std::string why = refusal(write_scratch(prefix, "cut.msh"));
      if (why == "(read)") {
        std::string trimmed = prefix;
        while (!trimmed.empty() && std::isspace(static_cast<unsigned char>(trimmed.back()))) trimmed.pop_back();
        const size_t line = trimmed.rfind('\n');
        EXPECT_EQ(trimmed.substr(line + 1, 4), "$End") << name << " cut at " << cut;
      } else {
        EXPECT_EQ(why.find('\n'), std::string::npos) << why;
        ++refused;
      }
    }
    EXPECT_GT(refused, 50) << name;
  }
}

// A copy of the 2.2 ascii file with `from` replaced by `to` (the first occurrence after `after`).
fs::path patched(const std::string& after, const std::string& from, const std::string& to, const std::string& name) {
  std::string s = test::file_bytes(kDir / "gmsh_tets_22a.msh");
  const size_t at = s.find(from, s.find(after));
  EXPECT_NE(at, std::string::npos) << from;
  return write_scratch(s.replace(at, from.size(), to), name);
}

// A view's values for nodes the file does not hold (Gmsh's 2.2 writer gives a node no saved
// element uses as -1) are dropped, as values of elements not read are; the others' stay.
TEST(Gmsh, ViewValuesOfNodesNotInTheFileAreDropped) {
  GmshFile msh(patched("$NodeData", "\n102\n1 3\n", "\n104\n-1 7\n99999 8\n1 3\n", "node_minus_one.msh"));
  expect_views_of_step(msh.read_step(0), 0);
}

TEST(Gmsh, DamagedFilesAreRefusedWithOneLine) {
  EXPECT_EQ(refusal(patched("$MeshFormat", "2.2 0 8", "3.0 0 8", "v3.msh")),
            "MSH version 3.0 is not read (4.1 and 2.2 are; gmsh -format msh41 converts)");
  EXPECT_EQ(refusal(patched("$MeshFormat", "2.2 0 8", "2.2 0 4", "size4.msh")), "data size 4 (8 is read)");
  EXPECT_EQ(refusal(write_scratch("$Nodes\n", "nohead.msh")), "not a Gmsh MSH file (no $MeshFormat at its start)");
  // The first tet's first node: a tag no node has.
  const std::string text = test::file_bytes(kDir / "gmsh_tets_22a.msh");
  std::istringstream lines(text.substr(text.find("$Elements")));
  std::string tet_line;
  for (std::string l; std::getline(lines, l);) {
    std::istringstream f(l);
    std::string tag, type;
    if (f >> tag >> type && type == "4") {
      tet_line = l;
      break;
    }
  }
  std::istringstream fields(tet_line);
  std::string tag, type, tags, physical, entity, first;
  fields >> tag >> type >> tags >> physical >> entity >> first;
  const std::string head = "\n" + tag + " 4 2 " + physical + " " + entity + " ";
  EXPECT_EQ(refusal(patched("$Elements", head + first + " ", head + "99999 ", "missing.msh")),
            "element " + tag + " (tet4): node tag 99999 is not in $Nodes");
  // Counts no file this size could hold: refused before anything is allocated for them.
  EXPECT_EQ(refusal(patched("$Nodes", "$Nodes\n102\n", "$Nodes\n999999999999999\n", "huge.msh")).substr(0, 41),
            "$Nodes: 999999999999999 items cannot fit ");
  EXPECT_EQ(refusal(patched("$Elements", "$Elements\n", "$Elements\n1000000000", "huge2.msh")).substr(0, 42),
            "$Elements: 1000000000519 items cannot fit ");
  EXPECT_EQ(refusal(patched("$NodeData", "\n3\n0\n1\n102\n", "\n3\n0\n1\n1000000000000\n", "huge3.msh")).substr(0, 46),
            "$NodeData 'f': 1000000000000 items cannot fit ");
  EXPECT_EQ(refusal(patched("$NodeData", "\n3\n0\n1\n102\n", "\n3\n0\n2\n102\n", "comps.msh")),
            "$NodeData 'f': 2 components (1, 3 or 9 are read)");
  // A view without a value on a node of the volume.
  std::string partial = test::file_bytes(kDir / "gmsh_tets_22a.msh");
  const size_t counts = partial.find("\n3\n0\n1\n102\n", partial.find("$NodeData"));
  const size_t entry = counts + 11;  // the first entry's line
  partial.erase(entry, partial.find('\n', entry) + 1 - entry);
  partial.replace(counts + 7, 3, "101");
  EXPECT_EQ(refusal(write_scratch(partial, "partial.msh")).substr(0, 39), "$NodeData 'f' step 0: no value for node");

  // Many empty view blocks of new steps, each of which would hold a value per node.
  std::string steps = test::file_bytes(kDir / "gmsh_tets_22a.msh");
  for (int step = 3; step < 3000; ++step)
    steps += "$NodeData\n1\n\"f\"\n1\n0\n3\n" + std::to_string(step) + "\n1\n0\n$EndNodeData\n";
  EXPECT_NE(refusal(write_scratch(steps, "steps.msh")).find("more view steps than the file holds values for"),
            std::string::npos);

  // 4.1 binary: the node count (size_t) of $Nodes' header made huge.
  std::string binary = test::file_bytes(kDir / "gmsh_tets_41b.msh");
  const size_t nodes = binary.find("$Nodes\n") + 7 + 8;
  binary.replace(nodes, 8, std::string("\xff\xff\xff\xff\xff\xff\xff\x0f", 8));
  EXPECT_EQ(refusal(write_scratch(binary, "huge41.msh")).substr(0, 9), "$Nodes: 1");
}

}  // namespace
}  // namespace vs
