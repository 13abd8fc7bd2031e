"""Writes the Fluent case and data files of this directory from the format's description (the
Fluent User's Guide appendix "Case and Data File Formats"), with a writer of its own, from meshes
VTK made; and beside them, as .vtu (VTK's own writer), the mesh and cell values the reader must
give (tests/io/fluent_test.cpp). Then reads every case and data file back with VTK's own
vtkFLUENTReader and stops unless VTK sees the same cells (the points of each) and values.

Run from this directory: /usr/bin/python3 make_fluent_files.py (python3-vtk9; the committed files
come from VTK 9.1.0).
- fluent_mixed.cas, fluent_mixed.dat: the Exodus test's warped tets, hexes, wedges and pyramids
  (../exodus/make_exodus_files.py) in two cell zones ("fluid": tets and hexes, "solid": wedges
  and pyramids), ASCII throughout: one node zone, cell zones of mixed element type (a type per
  cell), an interior face zone and a wall face zone of mixed face type (a node count per face).
  Data (ASCII 300 sections): pressure, temperature and the velocity components SV_U, SV_V, SV_W
  per cell, and a pressure on the wall faces (a face zone, which the reader skips); flow time 0.5.
  fluent_mixed.vtu: the mesh and the cell values.
- fluent_mixed_bin.cas, fluent_mixed_bin.dat, fluent_mixed_bin-2.dat: the same mesh as binary
  sections (3010 float64 nodes, 2012 cells, 2013 faces), data as 3300 float64 sections: the values
  above (flow time 0.5), and those of a second step (flow time 1.25; fluent_mixed_2.vtu).
- fluent_poly.cas, fluent_poly.dat: ../vtu/vtk_polyhedra.vtu (polyhedra at a 2:1 refinement step
  and hexes) with every cell a Fluent polyhedron (element type 7) of polygonal faces (face type
  5), binary: 2010 float32 nodes, 2013 faces; 2300 float32 data. fluent_poly.vtu: the same.
- fluent_mixed_gz.cas.gz, fluent_mixed_gz.dat.gz: fluent_mixed.cas and .dat gzipped (VTK reads
  no gzipped files; their contents are the checked ones).
Faces are written with their right-hand normal pointing into c0, as VTK's reader assumes (the
format's description does not say which way; volstream's reader does not depend on it).
"""
import gzip
import os
import shutil
import struct
import sys
import tempfile

import numpy as np
import vtk
from vtk.util import numpy_support

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "exodus"))
import make_exodus_files as exo  # noqa: E402

FLUENT_TYPE = {vtk.VTK_TETRA: 2, vtk.VTK_HEXAHEDRON: 4, vtk.VTK_PYRAMID: 5, vtk.VTK_WEDGE: 6, vtk.VTK_POLYHEDRON: 7}
SV_P, SV_T, SV_U, SV_V, SV_W = 1, 3, 111, 112, 113
NODE_ZONE, INTERIOR_ZONE, WALL_ZONE = 1, 4, 5
INTERIOR, WALL = 2, 3  # face zones' bc-types


def read_vtu(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def points_of(grid):
    return numpy_support.vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)


def cell_faces(grid, c):
    cell = grid.GetCell(c)
    return [[cell.GetFace(k).GetPointId(n) for n in range(cell.GetFace(k).GetNumberOfPoints())]
            for k in range(cell.GetNumberOfFaces())]


def cell_points(grid, c):
    return [grid.GetCell(c).GetPointId(k) for k in range(grid.GetCell(c).GetNumberOfPoints())]


def centroid(xyz, grid, c):
    return xyz[sorted(set(cell_points(grid, c)))].mean(axis=0)


def into(xyz, face, centre):
    """The face turned so that its right-hand normal points towards `centre`."""
    p = xyz[face]
    normal = sum(np.cross(p[n], p[(n + 1) % len(p)]) for n in range(len(p)))
    return face if np.dot(normal, centre - p.mean(axis=0)) > 0 else face[::-1]


def faces_of(grid, xyz):
    """Interior faces then boundary faces: [(1-based nodes, c0, c1)], normals into c0."""
    faces, owners = {}, {}
    for c in range(grid.GetNumberOfCells()):
        for face in cell_faces(grid, c):
            key = tuple(sorted(face))
            faces.setdefault(key, face)
            owners.setdefault(key, []).append(c)
    assert all(len(o) <= 2 for o in owners.values())
    rows = []
    for shared in (True, False):
        for key, face in faces.items():
            if (len(owners[key]) == 2) == shared:
                c0 = owners[key][0]
                nodes = into(xyz, face, centroid(xyz, grid, c0))
                rows.append(([n + 1 for n in nodes], c0 + 1, owners[key][1] + 1 if shared else 0))
    interior = sum(1 for o in owners.values() if len(o) == 2)
    return rows[:interior], rows[interior:]


class Case:
    """A mesh as Fluent's zones: nodes, cell zones [(id, name, first, last)] and face zones."""

    def __init__(self, grid, cell_zones):
        self.grid, self.xyz = grid, points_of(grid)
        self.cell_zones = cell_zones
        self.types = [FLUENT_TYPE[grid.GetCellType(c)] for c in range(grid.GetNumberOfCells())]
        self.interior, self.wall = faces_of(grid, self.xyz)


def hexes(values):
    return " ".join(format(v, "x") for v in values)


def binary_section(index, header, payload):
    return f"({index} ({header})(".encode() + payload + f")\nEnd of Binary Section   {index})\n".encode()


def face_rows(rows):
    """Each face's row in a zone of mixed (0) or polygonal (5) faces: its node count, nodes, c0, c1."""
    return [[len(nodes)] + nodes + [c0, c1] for nodes, c0, c1 in rows]


def write_case(case, name, binary, node_bytes=8, mixed_faces=True):
    n_cells, n_nodes = len(case.types), len(case.xyz)
    n_faces = len(case.interior) + len(case.wall)
    out = [b'(0 "volstream test: make_fluent_files.py")\n', b'(1 "volstream make_fluent_files.py")\n', b"(2 3)\n",
           f"(10 (0 1 {n_nodes:x} 0 3))\n".encode(), f"(12 (0 1 {n_cells:x} 0))\n".encode(),
           f"(13 (0 1 {n_faces:x} 0))\n".encode()]
    if binary:
        fmt = "<%d%s" % (3 * n_nodes, "d" if node_bytes == 8 else "f")
        index = 3010 if node_bytes == 8 else 2010
        out.append(binary_section(index, f"{NODE_ZONE:x} 1 {n_nodes:x} 1 3", struct.pack(fmt, *case.xyz.ravel())))
    else:
        rows = "\n".join(" ".join(repr(float(v)) for v in p) for p in case.xyz)
        out.append(f"(10 ({NODE_ZONE:x} 1 {n_nodes:x} 1 3)(\n{rows}\n))\n".encode())
    for zone, _, first, last in case.cell_zones:
        types = case.types[first - 1:last]
        element_type = types[0] if len(set(types)) == 1 else 0
        header = f"{zone:x} {first:x} {last:x} 1 {element_type:x}"
        if element_type != 0:
            out.append(f"(12 ({header}))\n".encode())
        elif binary:
            out.append(binary_section(2012, header, struct.pack("<%di" % len(types), *types)))
        else:
            out.append(f"(12 ({header})(\n{hexes(types)}\n))\n".encode())
    first = 1
    for zone, bc, rows in ((INTERIOR_ZONE, INTERIOR, case.interior), (WALL_ZONE, WALL, case.wall)):
        face_type = 0 if mixed_faces else 5
        header = f"{zone:x} {first:x} {first + len(rows) - 1:x} {bc:x} {face_type:x}"
        table = face_rows(rows)
        if binary:
            flat = [v for row in table for v in row]
            out.append(binary_section(2013, header, struct.pack("<%di" % len(flat), *flat)))
        else:
            out.append(f"(13 ({header})(\n" .encode() + "\n".join(hexes(r) for r in table).encode() + b"\n))\n")
        first += len(rows)
    out.append(b"(0 \"zones\")\n")
    for zone, zone_name, _, _ in case.cell_zones:
        out.append(f"(39 ({zone} fluid {zone_name} 1)())\n".encode())
    out.append(f"(39 ({INTERIOR_ZONE} interior default-interior 1)())\n".encode())
    out.append(f"(45 ({WALL_ZONE} wall walls)())\n".encode())
    with open(name, "wb") as f:
        f.write(b"".join(out))


def cell_values(case, step):
    """pressure (a function of the cell id), temperature (of its centroid), velocity."""
    centres = np.array([centroid(case.xyz, case.grid, c) for c in range(len(case.types))])
    ids = np.arange(len(case.types), dtype=np.float64)
    x, y, z = centres[:, 0], centres[:, 1], centres[:, 2]
    return {SV_P: 100 + 0.5 * ids + step, SV_T: 300 + x + 2 * y + 3 * z,
            SV_U: y * (1 + step), SV_V: -x, SV_W: 0.5 + step + 0 * x}


def write_data(case, name, step, flow_time, precision):
    """precision: "ascii", 4 (2300 sections) or 8 (3300)."""
    values = cell_values(case, step)
    out = [b'(0 "volstream test data")\n',
           f"(37 (\n(flow-time {flow_time!r})\n(time-step 0.25)\n(case-config ((rp-seg? . #t)))\n))\n".encode(),
           f"(33 ({len(case.types)} {len(case.interior) + len(case.wall)} {len(case.xyz)}))\n".encode()]
    wall_first = len(case.interior) + 1
    sections = [(sv, zone, first, last, values[sv][first - 1:last]) for sv in values
                for zone, _, first, last in case.cell_zones]
    sections.append((SV_P, WALL_ZONE, wall_first, wall_first + len(case.wall) - 1, np.full(len(case.wall), -1e30)))
    for sv, zone, first, last, v in sections:
        header = f"{sv} {zone} 1 0 0 {first} {last}"
        if precision == "ascii":
            out.append(f"(300 ({header})(\n".encode() + "\n".join(repr(float(a)) for a in v).encode() + b"\n))\n")
        else:
            index = 3300 if precision == 8 else 2300
            out.append(binary_section(index, header, struct.pack("<%d%s" % (len(v), "d" if precision == 8 else "f"), *v)))
    with open(name, "wb") as f:
        f.write(b"".join(out))
    return values


def expected_grid(case, values, float32):
    point_values = {}
    cells = {"pressure": values[SV_P], "temperature": values[SV_T]}
    if float32:
        cells = {k: v.astype(np.float32).astype(np.float64) for k, v in cells.items()}
    grid = exo.with_values(case.grid, point_values, cells)
    velocity = np.stack([values[SV_U], values[SV_V], values[SV_W]], axis=1)
    if float32:
        velocity = velocity.astype(np.float32).astype(np.float64)
    a = numpy_support.numpy_to_vtk(np.ascontiguousarray(velocity), deep=True)
    a.SetName("velocity")
    grid.GetCellData().AddArray(a)
    return grid


VTK_NAMES = {SV_P: "PRESSURE", SV_T: "TEMPERATURE", SV_U: "X_VELOCITY", SV_V: "Y_VELOCITY", SV_W: "Z_VELOCITY"}


def check_with_vtk(cas, dat, case, values, float32):
    """VTK's reader must see each cell zone's cells on the same points, with the same values."""
    with tempfile.TemporaryDirectory() as tmp:  # VTK reads the .dat of the case's name
        shutil.copy(cas, os.path.join(tmp, "case.cas"))
        shutil.copy(dat, os.path.join(tmp, "case.dat"))
        reader = vtk.vtkFLUENTReader()
        reader.SetFileName(os.path.join(tmp, "case.cas"))
        reader.UpdateInformation()
        reader.EnableAllCellArrays()
        reader.Update()
        blocks = reader.GetOutput()
    assert blocks.GetNumberOfBlocks() == len(case.cell_zones), (cas, blocks.GetNumberOfBlocks())
    place = lambda g, ids: sorted(tuple(np.round(g.GetPoint(i), 6)) for i in ids)
    for b, (_, _, first, last) in enumerate(case.cell_zones):
        theirs = blocks.GetBlock(b)
        assert theirs.GetNumberOfCells() == last - first + 1, (cas, b, theirs.GetNumberOfCells())
        for k in range(theirs.GetNumberOfCells()):
            c = first - 1 + k
            assert place(theirs, cell_points(theirs, k)) == place(case.grid, set(cell_points(case.grid, c))), \
                (cas, "cell", c)
        for sv, name in VTK_NAMES.items():
            got = numpy_support.vtk_to_numpy(theirs.GetCellData().GetArray(name))
            want = values[sv][first - 1:last]
            tolerance = 1e-6 * np.abs(want).max() if float32 else 1e-12
            assert np.allclose(got, want, rtol=0, atol=tolerance), (cas, dat, name, b)
    print(f"{cas} + {dat}: VTK's Fluent reader sees the same {len(case.types)} cells and values")


def mixed_case():
    grid = exo.mixed_grid()
    types = [grid.GetCellType(c) for c in range(grid.GetNumberOfCells())]
    fluid = sum(1 for t in types if t in (vtk.VTK_TETRA, vtk.VTK_HEXAHEDRON))
    assert types[:fluid].count(vtk.VTK_WEDGE) == 0
    return Case(grid, [(2, "fluid", 1, fluid), (3, "solid", fluid + 1, len(types))])


def poly_case():
    grid = read_vtu(os.path.join(HERE, "..", "vtu", "vtk_polyhedra.vtu"))
    plain = vtk.vtkUnstructuredGrid()  # the cells alone: the test's values are the data file's
    plain.DeepCopy(grid)
    plain.GetPointData().Initialize()
    plain.GetCellData().Initialize()
    case = Case(plain, [(2, "cells", 1, grid.GetNumberOfCells())])
    case.types = [7] * len(case.types)  # every cell a Fluent polyhedron, the hexes too
    return case


def main():
    os.chdir(HERE)
    mixed = mixed_case()
    write_case(mixed, "fluent_mixed.cas", binary=False)
    values = write_data(mixed, "fluent_mixed.dat", 0, 0.5, "ascii")
    exo.write_vtu(expected_grid(mixed, values, False), "fluent_mixed.vtu")
    check_with_vtk("fluent_mixed.cas", "fluent_mixed.dat", mixed, values, False)

    write_case(mixed, "fluent_mixed_bin.cas", binary=True)
    write_data(mixed, "fluent_mixed_bin.dat", 0, 0.5, 8)
    check_with_vtk("fluent_mixed_bin.cas", "fluent_mixed_bin.dat", mixed, values, False)
    values2 = write_data(mixed, "fluent_mixed_bin-2.dat", 1, 1.25, 8)
    exo.write_vtu(expected_grid(mixed, values2, False), "fluent_mixed_2.vtu")
    check_with_vtk("fluent_mixed_bin.cas", "fluent_mixed_bin-2.dat", mixed, values2, False)

    poly = poly_case()
    write_case(poly, "fluent_poly.cas", binary=True, node_bytes=4, mixed_faces=False)
    values = write_data(poly, "fluent_poly.dat", 0, 0.0, 4)
    exo.write_vtu(expected_grid(poly, values, True), "fluent_poly.vtu")
    check_with_vtk("fluent_poly.cas", "fluent_poly.dat", poly, values, True)

    for ext in ("cas", "dat"):
        with open(f"fluent_mixed.{ext}", "rb") as src, gzip.GzipFile(f"fluent_mixed_gz.{ext}.gz", "wb", mtime=0) as dst:
            dst.write(src.read())


if __name__ == "__main__":
    main()
