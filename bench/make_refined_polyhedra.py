"""Writes a mesh as OpenFOAM's snappyHexMesh leaves one, for benchmarks of volstream's polyhedra:
a grid of N^3 hexes over the unit cube whose cells inside a sphere are each split into 8 (one
refinement level, 2:1). The coarse cells that touch the refined region keep their shape but get
the refined region's points on their edges and faces, so they are VTK polyhedra (type 42) with
pentagonal faces, or quads split in four, as foamToVTK writes them; every other cell is a hex.
Point field "density": a sum of Gaussians (up to about 1.1, as the demo meshes' density, so that
bench/umesh_vs_vtk.sh's looks apply), smooth across the refinement step.

    /usr/bin/python3 bench/make_refined_polyhedra.py N OUT.vtu [--all-polyhedra]

With --all-polyhedra the hexes are written as polyhedra too, as Fluent's and CGNS's polyhedral
meshes (NFACE_n) give every cell (volstream reads those back as hexes). Debian's python3-vtk9.
"""
import sys

import numpy as np
import vtk
from vtk.util import numpy_support


def refined(n):
    """Which coarse cells are split: those whose centre lies within 0.3 of (0.5, 0.5, 0.45)."""
    c = (np.arange(n) + 0.5) / n
    x, y, z = np.meshgrid(c, c, c, indexing="ij")
    return (x - 0.5) ** 2 + (y - 0.5) ** 2 + (z - 0.45) ** 2 < 0.3 ** 2


# A cell's six faces as corner offsets (in its own units), each outward by the right-hand rule.
FACES = [((0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)), ((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)),
         ((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)), ((0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)),
         ((0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)), ((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1))]
HEX = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]


def write_with_density(grid, points, out):
    """Adds the point field "density" (a sum of three Gaussians, up to about 1.1) at `points`
    (an N x 3 array, the grid's) and writes the grid to `out` (.vtu, appended raw)."""
    density = np.zeros(len(points))
    for centre, width in (((0.5, 0.5, 0.45), 0.12), ((0.3, 0.6, 0.5), 0.08), ((0.7, 0.35, 0.55), 0.1)):
        density += np.exp(-np.sum((points - centre) ** 2, axis=1) / (2 * width ** 2))
    array = numpy_support.numpy_to_vtk(density, deep=True)
    array.SetName("density")
    grid.GetPointData().AddArray(array)
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetInputData(grid)
    writer.SetFileName(out)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.Write()


def main():
    n, out = int(sys.argv[1]), sys.argv[2]
    all_polyhedra = "--all-polyhedra" in sys.argv
    split = refined(n)
    m = 2 * n + 1  # the fine lattice: a coarse cell spans 2 units, a fine cell 1
    used = np.zeros((m, m, m), dtype=bool)
    used[::2, ::2, ::2] = True
    for i, j, k in np.argwhere(split):
        used[2 * i:2 * i + 3, 2 * j:2 * j + 3, 2 * k:2 * k + 3] = True
    ids = -np.ones((m, m, m), dtype=np.int64)
    ids[used] = np.arange(int(used.sum()))
    lattice = np.argwhere(used)  # row-major, as the ids were given
    points = lattice.astype(np.float64) / (2 * n)

    grid = vtk.vtkUnstructuredGrid()
    cell = vtk.vtkIdList()

    def add(cell_type, values):
        cell.Reset()
        for v in values:
            cell.InsertNextId(int(v))
        grid.InsertNextCell(cell_type, cell)

    def add_polyhedron(faces):
        stream = [len(faces)]
        for f in faces:
            stream += [len(f)] + f
        add(vtk.VTK_POLYHEDRON, stream)

    def corner_faces(origin, size):
        return [[ids[tuple(np.add(origin, np.multiply(c, size)))] for c in f] for f in FACES]

    def coarse_faces(origin):
        """A coarse cell's faces with the points of the refined region on them."""
        faces = []
        for f in FACES:
            corners = [np.add(origin, np.multiply(c, 2)) for c in f]
            centre = tuple((corners[0] + corners[2]) // 2)
            mids = [tuple((corners[q] + corners[(q + 1) % 4]) // 2) for q in range(4)]
            if used[centre]:  # the neighbour is refined: four quads
                for q in range(4):
                    faces.append([ids[tuple(corners[q])], ids[mids[q]], ids[centre], ids[mids[(q + 3) % 4]]])
                continue
            polygon = []
            for q in range(4):
                polygon.append(ids[tuple(corners[q])])
                if used[mids[q]]:
                    polygon.append(ids[mids[q]])
            faces.append(polygon)
        return faces

    for i in range(n):
        for j in range(n):
            for k in range(n):
                origin = (2 * i, 2 * j, 2 * k)
                if split[i, j, k]:
                    for a, b, c in HEX:
                        fine = (2 * i + a, 2 * j + b, 2 * k + c)
                        if all_polyhedra:
                            add_polyhedron(corner_faces(fine, 1))
                        else:
                            add(vtk.VTK_HEXAHEDRON, [ids[tuple(np.add(fine, h))] for h in HEX])
                    continue
                faces = coarse_faces(origin)
                if all_polyhedra or any(len(f) != 4 for f in faces) or len(faces) != 6:
                    add_polyhedron(faces)
                else:
                    add(vtk.VTK_HEXAHEDRON, [ids[tuple(np.add(origin, np.multiply(h, 2)))] for h in HEX])
    vtk_points = vtk.vtkPoints()
    vtk_points.SetData(numpy_support.numpy_to_vtk(points, deep=True))
    grid.SetPoints(vtk_points)
    write_with_density(grid, points, out)
    types = numpy_support.vtk_to_numpy(grid.GetCellTypesArray())
    print(f"{out}: {grid.GetNumberOfCells()} cells ({int((types == 42).sum())} polyhedra, "
          f"{int((types == 12).sum())} hexes), {len(points)} points")


if __name__ == "__main__":
    main()
