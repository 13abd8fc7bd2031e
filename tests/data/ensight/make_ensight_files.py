"""Writes the EnSight Gold test cases of this directory (tests/io/ensight_test.cpp):

- ascii/ and big_endian/: one mesh written here from the EnSight Gold format's description, as
  ASCII and as C Binary in big-endian byte order: part 1 holds a cube [0,2]^3 whose face x = 2 is
  split in four (nfaced, with pentagons), four unit hexes of [2,3]x[0,2]^2 (hexa8), a pyramid on
  the cube's face x = 0 and a hexagonal prism (nfaced), a wedge (penta6) and a tet (tetra4);
  part 2 the four unit hexes of [3,4]x[0,2]^2 on nodes of its own; part 3 the quads of the face
  x = 4 (a boundary part). Node and element ids given, extents. Two steps (files numbered 0 and
  1, times 0 and 0.5): per node f = 1 + 2x + 3y + 4z (+ 10 at the second step) and the vector
  v = (x, y, z); per element "cell" (1, 2, 3, ... within each part).
- vtk/: volstream's demo mixed mesh (tests/data/ensight/vtk/mixed.vtu, written by `volstream demo
  mixed --elements 300 --steps 1 --write-mesh`) as VTK's vtkEnSightWriter writes it (C Binary).
- vtk_quadratic/: the quadratic cells of ../vtu/vtk_quadratic.vtu that EnSight has (tetra10,
  pyramid13, penta15, hexa20), as vtkEnSightWriter writes them.

Each case is read back with VTK's vtkGenericEnSightReader, which prints what it found. Run from
this directory with Debian's python3-vtk9: /usr/bin/python3 make_ensight_files.py
"""
import os
import struct

import vtk

# Coordinates and values with at most six significant digits, so the ASCII files' e12.5 holds them.
HEXAGON = [(6.0, 1.0), (5.75, 1.43301), (5.25, 1.43301), (5.0, 1.0), (5.25, 0.56699), (5.75, 0.56699)]


def mesh():
    """Parts as lists of (type, elements); an element is a node list, an nfaced one a face list."""
    parts = []
    nodes, index = [], {}

    def node(p):
        p = tuple(float(c) for c in p)
        if p not in index:
            index[p] = len(nodes)
            nodes.append(p)
        return index[p] + 1  # EnSight's node numbers start at 1

    def hexa(o):
        return [node((o[0] + a, o[1] + b, o[2] + c)) for c in (0, 1) for a, b in ((0, 0), (1, 0), (1, 1), (0, 1))]

    cube = [[(0, 0, 0), (0, 2, 0), (2, 2, 0), (2, 1, 0), (2, 0, 0)], [(0, 0, 2), (2, 0, 2), (2, 1, 2), (2, 2, 2), (0, 2, 2)],
            [(0, 0, 0), (2, 0, 0), (2, 0, 1), (2, 0, 2), (0, 0, 2)], [(0, 2, 0), (0, 2, 2), (2, 2, 2), (2, 2, 1), (2, 2, 0)],
            [(0, 0, 0), (0, 0, 2), (0, 2, 2), (0, 2, 0)]]
    cube += [[(2, j, k), (2, j + 1, k), (2, j + 1, k + 1), (2, j, k + 1)] for j in (0, 1) for k in (0, 1)]
    side = [(0, 0, 0), (0, 0, 2), (0, 2, 2), (0, 2, 0)]
    pyramid = [list(reversed(side))] + [[side[n], side[(n + 1) % 4], (-1, 1, 1)] for n in range(4)]
    bottom, top = [(x, y, 0) for x, y in HEXAGON], [(x, y, 1) for x, y in HEXAGON]
    prism = [list(reversed(bottom)), top] + [[bottom[n], bottom[(n + 1) % 6], top[(n + 1) % 6], top[n]] for n in range(6)]
    nfaced = [[[node(p) for p in face] for face in cell] for cell in (cube, pyramid, prism)]
    hexes = [hexa((2, j, k)) for j in (0, 1) for k in (0, 1)]
    # EnSight's penta6: the triangle 1-2-3 with its normal towards 4-5-6.
    wedge = [node(p) for p in ((7, 0, 0), (8, 0, 0), (7, 1, 0), (7, 0, 1), (8, 0, 1), (7, 1, 1))]
    tet = [node(p) for p in ((9, 0, 0), (10, 0, 0), (9, 1, 0), (9, 0, 1))]
    parts.append((nodes, [("hexa8", hexes), ("nfaced", nfaced), ("penta6", [wedge]), ("tetra4", [tet])]))

    nodes, index = [], {}
    parts.append((nodes, [("hexa8", [hexa((3, j, k)) for j in (0, 1) for k in (0, 1)])]))
    nodes, index = [], {}
    quads = [[node((4, j + a, k + b)) for a, b in ((0, 0), (1, 0), (1, 1), (0, 1))] for j in (0, 1) for k in (0, 1)]
    parts.append((nodes, [("quad4", quads)]))
    return parts


def f(p, step):
    return 1 + 2 * p[0] + 3 * p[1] + 4 * p[2] + 10 * step


class Writer:
    """ASCII lines, or C Binary records in the given byte order."""

    def __init__(self, path, binary, order):
        self.out = open(path, "wb")
        self.binary, self.order = binary, order

    def line(self, text):
        self.out.write(text.encode().ljust(80, b"\0") if self.binary else (text + "\n").encode())

    def ints(self, values, per_line=1):
        values = list(values)
        if self.binary:
            self.out.write(struct.pack(f"{self.order}{len(values)}i", *values))
        else:
            for i in range(0, len(values), per_line):
                self.out.write(("".join("%10d" % v for v in values[i:i + per_line]) + "\n").encode())

    def floats(self, values):
        values = list(values)
        if self.binary:
            self.out.write(struct.pack(f"{self.order}{len(values)}f", *values))
        else:
            for v in values:
                self.out.write(("%12.5e\n" % v).encode())


def write_case(directory, binary, order=">"):
    os.makedirs(directory, exist_ok=True)
    parts = mesh()
    g = Writer(f"{directory}/mesh.geo", binary, order)
    if binary:
        g.line("C Binary")
    g.line("volstream test mesh")
    g.line("")  # a blank description
    g.line("node id given")
    g.line("element id given")
    g.line("extents")
    everything = [p for nodes, _ in parts for p in nodes]
    if binary:
        g.floats(v for axis in range(3) for v in (min(p[axis] for p in everything), max(p[axis] for p in everything)))
    else:
        for axis in range(3):
            g.out.write(("%12.5e%12.5e\n" % (min(p[axis] for p in everything), max(p[axis] for p in everything))).encode())
    for number, (nodes, blocks) in enumerate(parts, 1):
        g.line("part")
        g.ints([number])
        g.line(f"part {number}")
        g.line("coordinates")
        g.ints([len(nodes)])
        g.ints(range(101, 101 + len(nodes)))
        for axis in range(3):
            g.floats(p[axis] for p in nodes)
        for kind, cells in blocks:
            g.line(kind)
            g.ints([len(cells)])
            g.ints(range(1001, 1001 + len(cells)))
            if kind == "nfaced":
                g.ints(len(cell) for cell in cells)
                g.ints(len(face) for cell in cells for face in cell)
                for cell in cells:
                    for face in cell:
                        g.ints(face, per_line=len(face))
            else:
                for cell in cells:
                    g.ints(cell, per_line=len(cell))
    g.out.close()
    def node_variable(name, step, components):
        """components: functions of a node and the step, each written for all nodes in turn."""
        w = Writer(f"{directory}/{name}.{step}", binary, order)
        w.line(name)
        for number, (nodes, _) in enumerate(parts, 1):
            w.line("part")
            w.ints([number])
            w.line("coordinates")
            for component in components:
                w.floats(component(p, step) for p in nodes)
        w.out.close()

    for step in (0, 1):
        node_variable("f", step, [f])
        node_variable("v", step, [lambda p, _, axis=axis: p[axis] for axis in range(3)])
        w = Writer(f"{directory}/cell.{step}", binary, order)
        w.line("cell")
        for number, (_, blocks) in enumerate(parts, 1):
            w.line("part")
            w.ints([number])
            first = 1
            for kind, cells in blocks:
                w.line(kind)
                w.floats(range(first, first + len(cells)))
                first += len(cells)
        w.out.close()
    with open(f"{directory}/mesh.case", "w") as case:
        case.write("FORMAT\ntype: ensight gold\n\nGEOMETRY\nmodel: mesh.geo\n\nVARIABLE\n"
                   "scalar per node: 1 f f.*\nvector per node: 1 v v.*\nscalar per element: 1 cell cell.*\n\n"
                   "TIME\ntime set: 1\nnumber of steps: 2\nfilename start number: 0\nfilename increment: 1\n"
                   "time values:\n0.0\n0.5\n")


def write_vtk_case():
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName("vtk/mixed.vtu")
    writer = vtk.vtkEnSightWriter()
    writer.SetInputConnection(reader.GetOutputPort())
    writer.SetPath("vtk")
    writer.SetBaseName("mixed")
    writer.Write()
    writer.WriteCaseFile(1)


def write_vtk_quadratic_case():
    """The quadratic cells of ../vtu/vtk_quadratic.vtu that EnSight has (tetra10, pyramid13,
    penta15, hexa20: cells 0, 1, 3, 4 and 6) as vtkEnSightWriter writes them, in vtk_quadratic/."""
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName("../vtu/vtk_quadratic.vtu")
    ids = vtk.vtkIdList()
    for c in (0, 1, 3, 4, 6):
        ids.InsertNextId(c)
    extract = vtk.vtkExtractCells()
    extract.SetInputConnection(reader.GetOutputPort())
    extract.SetCellList(ids)
    extract.Update()
    cells = extract.GetOutput()
    cells.GetCellData().RemoveArray("vtkOriginalCellIds")
    os.makedirs("vtk_quadratic", exist_ok=True)
    writer = vtk.vtkEnSightWriter()
    writer.SetInputData(cells)
    writer.SetPath("vtk_quadratic")
    writer.SetBaseName("quadratic")
    writer.Write()
    writer.WriteCaseFile(1)


def check_with_vtk(case):
    reader = vtk.vtkGenericEnSightReader()
    reader.SetCaseFileName(os.path.abspath(case))
    reader.ReadAllVariablesOn()
    reader.Update()
    out = reader.GetOutput()
    for b in range(out.GetNumberOfBlocks()):
        block = out.GetBlock(b)
        print(f"{case} part {b}: {block.GetNumberOfPoints()} points, {block.GetNumberOfCells()} cells,",
              "point arrays", [block.GetPointData().GetArrayName(i) for i in range(block.GetPointData().GetNumberOfArrays())],
              "cell arrays", [block.GetCellData().GetArrayName(i) for i in range(block.GetCellData().GetNumberOfArrays())])


if __name__ == "__main__":
    write_case("ascii", binary=False)
    write_case("big_endian", binary=True, order=">")
    write_vtk_case()
    write_vtk_quadratic_case()
    for c in ("ascii/mesh.case", "big_endian/mesh.case", "vtk/mixed.0.case", "vtk_quadratic/quadratic.0.case"):
        check_with_vtk(c)
