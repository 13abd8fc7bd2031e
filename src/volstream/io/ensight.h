// EnSight Gold (the case format that Fluent, STAR-CCM+, CFX and OpenFOAM's foamToEnsight write
// for visualisation): a .case file naming a geometry file and variable files, over time steps.
// Read here: "C Binary" (either byte order) and ASCII files; unstructured parts of tetra4,
// pyramid5, penta6, hexa8, nfaced (polyhedra, split as umesh/polyhedra.h says) and the quadratic
// tetra10, pyramid13, penta15 and hexa20 (split as umesh/quadratic.h says) elements, node and
// element ids off, assign, given or ignore; scalar and vector variables per node and per
// element; one time set (numbered files, '*' wildcards). Surface and line elements (the
// boundary parts beside the volume) and ghost elements (g_*) are skipped, with their values;
// parts without volume elements are left out; `--region` reads only the parts named. Refused
// with one line: Fortran binary files, structured (block) parts, partial or undefined variable
// values, several time sets, single-file (FILE section) cases.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "volstream/umesh/mesh_data.h"
#include "volstream/umesh/polyhedra.h"

namespace vs {

struct EnsightCase {
  struct Variable {
    std::string name, file;  // file: relative to the case's directory, may hold '*' wildcards
    bool per_element = false;
    int components = 1;  // scalar 1, vector 3
  };
  std::filesystem::path dir;
  std::string geometry;
  std::vector<Variable> variables;
  std::vector<double> times{0.0};        // one per step
  std::vector<int64_t> file_numbers{0};  // what replaces a file name's '*'s at each step
  bool geometry_changes() const { return geometry.find('*') != std::string::npos; }
};

// InputError naming the file for anything it does not understand (see above).
EnsightCase read_ensight_case(const std::filesystem::path& file);

// A file of the case at a step: its '*'s replaced by the step's file number, zero-padded to as
// many digits as there are '*'s.
std::filesystem::path ensight_step_file(const EnsightCase& c, const std::string& name, size_t step);

// The parts of a geometry file as read, before any variable: each part's volume elements (an
// nfaced element as a polyhedron, its faces in `faces`) on the part's own nodes, and every
// element block of the part in file order, so that per-element variables can be matched.
struct EnsightGeometry {
  struct Block {
    std::string type;
    uint64_t count = 0;
    bool kept = false;  // a volume element type
  };
  struct Part {
    int64_t number = 0;
    std::string description;  // the line after the part's number, trimmed
    bool wanted = true;       // read into the mesh (--region: one of the parts asked for)
    uint64_t node_count = 0;  // the part's nodes in the file (in `mesh` only where wanted)
    MeshData mesh;            // empty where not wanted: its numbers were read past
    PolyhedronFaces faces;
    std::vector<Block> blocks;
    mutable SplitMemo polyhedra_split;  // for the next step on this geometry
  };
  std::vector<Part> parts;
  bool binary = false, big_endian = false;
  mutable SplitMemo quadratic_split;
};
// `parts`: those to read into the mesh, by description or number (the others' nodes, elements and
// values are read past, not kept); a part the geometry lacks is refused, listing its parts. Empty: all.
EnsightGeometry read_ensight_geometry(const std::filesystem::path& file, const std::vector<std::string>& parts = {});

// A step: the geometry's parts with the step's variables (point and cell data), polyhedra split,
// parts joined into one mesh (umesh/mesh_pieces.h: the nodes they share welded), checked. The
// splits are remembered in `geometry`, so the next step's reuse them.
MeshData read_ensight_step(const EnsightCase& c, const EnsightGeometry& geometry, size_t step);

}  // namespace vs
