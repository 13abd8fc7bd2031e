"""Writes a second-order finite-element mesh over the unit cube, for benchmarks of volstream's
quadratic cells: N^3 cubes, each as 6 quadratic tets (tet10, VTK type 24: the cube's Kuhn split,
all six around its diagonal from (0,0,0) to (1,1,1)) or as one quadratic hexahedron (hex20,
type 25), every node moved by the same smooth map so that the cells are curved, as a mesh of a
curved part is. Point field "density": the sum of Gaussians of bench/make_refined_polyhedra.py
(up to about 1.1, so that bench/umesh_vs_vtk.sh's looks apply), at every node.

    /usr/bin/python3 bench/make_quadratic_mesh.py N OUT.vtu [tet10|hex20|lagrangeP]

lagrangeP (P = 1..10): N^3 Lagrange hexahedra (VTK type 72) of order P, as VTK's vtkCellTypeSource
makes them, curved in the same way. volstream splits each tet10 into 8 tets, each hex20 into 8
hexes and each Lagrange hexahedron into P^3 hexes (docs/formats.md). Debian's python3-vtk9.
"""
import itertools
import sys

import numpy as np
import vtk
from vtk.util import numpy_support

from make_refined_polyhedra import write_with_density

# VTK's node order: the corners, then the mid-edge nodes of these corner pairs.
TET10_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
HEX_CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
HEX20_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]


def kuhn_tets():
    """The 6 tets of a unit cube along its diagonal, as corner offsets, each in VTK's
    orientation (its first three corners turn clockwise seen from the fourth)."""
    tets = []
    for axes in itertools.permutations(range(3)):
        path = [np.zeros(3, dtype=int)]
        for a in axes:
            path.append(path[-1] + np.eye(3, dtype=int)[a])
        p = [tuple(v) for v in path]
        if np.dot(np.cross(np.subtract(p[1], p[0]), np.subtract(p[2], p[0])), np.subtract(p[3], p[0])) < 0:
            p[1], p[2] = p[2], p[1]
        tets.append(p)
    return tets


def cells(n, kind):
    """Node coordinates on the lattice of half cells (integers 0..2n), one row per cell."""
    origins = 2 * np.array(list(itertools.product(range(n), repeat=3)))[:, ::-1]  # x fastest
    shapes = kuhn_tets() if kind == "tet10" else [HEX_CORNERS]
    edges = TET10_EDGES if kind == "tet10" else HEX20_EDGES
    rows = []
    for corners in shapes:
        c = 2 * np.array(corners)
        nodes = list(c) + [(c[a] + c[b]) // 2 for a, b in edges]
        rows.append(origins[:, None, :] + np.array(nodes)[None, :, :])
    return np.concatenate(rows, axis=0) if len(rows) > 1 else rows[0]


def curved(x, y, z):
    return np.stack([x + 0.03 * np.sin(np.pi * y), y + 0.03 * np.sin(np.pi * z), z + 0.03 * np.sin(np.pi * x)], axis=1)


def lagrange_hexahedra(n, order, out):
    source = vtk.vtkCellTypeSource()
    source.SetCellType(vtk.VTK_LAGRANGE_HEXAHEDRON)
    source.SetCellOrder(order)
    source.SetBlocksDimensions(n, n, n)
    source.Update()
    grid = source.GetOutput()
    while grid.GetPointData().GetNumberOfArrays():
        grid.GetPointData().RemoveArray(0)
    unit = numpy_support.vtk_to_numpy(grid.GetPoints().GetData()) / n
    points = curved(unit[:, 0], unit[:, 1], unit[:, 2])
    grid.GetPoints().SetData(numpy_support.numpy_to_vtk(points, deep=True))
    write_with_density(grid, points, out)
    print(f"{out}: {grid.GetNumberOfCells()} Lagrange hexahedra of order {order}, {len(points)} points")


def main():
    n, out = int(sys.argv[1]), sys.argv[2]
    kind = sys.argv[3] if len(sys.argv) > 3 else "tet10"
    if kind.startswith("lagrange"):
        return lagrange_hexahedra(n, int(kind[len("lagrange"):]), out)
    lattice = cells(n, kind)
    m = 2 * n + 1
    keys = (lattice[..., 0] * m + lattice[..., 1]) * m + lattice[..., 2]
    used, connectivity = np.unique(keys.ravel(), return_inverse=True)
    half = np.stack([used // (m * m), (used // m) % m, used % m], axis=1) / (2.0 * n)
    x, y, z = half[:, 0], half[:, 1], half[:, 2]
    points = curved(x, y, z)
    per_cell = lattice.shape[1]
    cell_type = vtk.VTK_QUADRATIC_TETRA if kind == "tet10" else vtk.VTK_QUADRATIC_HEXAHEDRON
    grid = vtk.vtkUnstructuredGrid()
    vtk_points = vtk.vtkPoints()
    vtk_points.SetData(numpy_support.numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    cell_array = vtk.vtkCellArray()
    offsets = np.arange(0, connectivity.size + 1, per_cell, dtype=np.int64)
    cell_array.SetData(numpy_support.numpy_to_vtkIdTypeArray(offsets, deep=True),
                       numpy_support.numpy_to_vtkIdTypeArray(connectivity.astype(np.int64), deep=True))
    grid.SetCells(cell_type, cell_array)
    write_with_density(grid, points, out)
    print(f"{out}: {grid.GetNumberOfCells()} {kind} cells, {len(points)} points")


if __name__ == "__main__":
    main()
