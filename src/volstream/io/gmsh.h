// Gmsh's MSH files (written by Gmsh, and by FEniCS/DOLFINx, Elmer, GetDP and other finite-element
// codes that use its format), from the format's description in Gmsh's manual ("MSH file
// format"): versions 4.1 (Gmsh's default since 4.0) and 2.2, ascii and binary, either byte order.
// Read: the nodes (4.1: entity blocks, tags in any order, sparse, with or without parametric
// coordinates); the volume elements 4 (tet4), 5 (hex8), 6 (prism6), 7 (pyramid5) and the
// second-order 11 (tet10), 17 (hex20), 12 (hex27), 18 (prism15), 13 (prism18), 19 (pyramid13),
// their node orders turned into VTK's and the quadratic ones split as umesh/quadratic.h says;
// points, lines, triangles and quadrangles are left out. $NodeData views become point data and
// $ElementData views cell data (1, 3 or 9 components, several partitions of one step joined), by
// name; the file's time steps are the distinct time-step indices of its views, with their times,
// and a view given at one step only holds at every step (a material id written once beside a
// temperature's steps). $ElementNodeData views are left out (summary() says so); $Entities,
// $PhysicalNames, $Periodic, $PartitionedEntities, $InterpolationScheme and any other section are
// skipped, but for a choice of physical groups (below). MSH 2.2 writes an element once for each
// physical group that holds it, each copy under a number of its own: the copies are read as one
// element (the same type and nodes, in order, as one read before), their numbers naming it.
// Refused with one line: other versions (1.0, 2.0, 2.1, 3.0, 4.0), other volume element types
// (the 14-node pyramid, which VTK lacks; third and higher orders), element nodes that are no
// node's tag, views missing values on a node or element the volume uses, counts larger than the
// file could hold, and files cut short.
#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "volstream/umesh/mesh_data.h"

namespace vs {

class GmshFile {
 public:
  // Reads the whole file (mesh and views); InputError naming the file for anything it does not
  // read (see above). `groups`: the physical groups of volumes to read, by name ($PhysicalNames)
  // or number, and not the other elements nor the nodes only they use (4.1: the volumes of
  // $Entities, or of a partitioned mesh's $PartitionedEntities, in those groups; 2.2: the
  // elements whose first tag, or one of whose copies' first tag, is one); a group the file lacks
  // is refused, listing the file's. Empty: every element.
  explicit GmshFile(const std::filesystem::path& file, const std::vector<std::string>& groups = {});
  ~GmshFile();
  GmshFile(const GmshFile&) = delete;
  GmshFile& operator=(const GmshFile&) = delete;

  // The views' time steps, by index; a file without views (a mesh alone) has one, at time 0.
  size_t step_count() const;
  double step_time(size_t step) const;
  // The mesh with the step's views, quadratic elements split, checked (check_mesh).
  MeshData read_step(size_t step) const;
  // "MSH 4.1 binary: tet4 x 120, prism6 x 16", and what was left out, for `info`.
  std::string summary() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vs
