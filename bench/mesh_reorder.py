#!/usr/bin/python3
"""Writes a .vtu with the cells and points of another in a different order (python3-vtk9, numpy):
`random` (cells and points shuffled, as a file with no locality would give them) or `morton`
(cells by the Morton code of their centres, points by first use). The mesh, its point data and
every image rendered from it are the same; only the order in the file changes. Used to measure
how the stored spatial order (src/volstream/umesh/spatial_order.h) serves badly ordered input
(bench/RESULTS.md).

usage: bench/mesh_reorder.py IN.vtu OUT.vtu random|morton [--seed 1]
"""
import argparse

import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy


def read(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def cell_centres(points, connectivity, offsets):
    counts = np.diff(offsets)
    centres = np.zeros((len(counts), 3))
    for k in np.unique(counts):
        cells = np.where(counts == k)[0]
        corners = offsets[cells][:, None] + np.arange(k)[None, :]
        centres[cells] = points[connectivity[corners]].mean(axis=1)
    return centres


def morton_codes(centres, bits=10):
    lower, upper = centres.min(0), centres.max(0)
    q = ((centres - lower) / np.maximum(upper - lower, 1e-30) * ((1 << bits) - 1)).astype(np.uint64)
    codes = np.zeros(len(centres), np.uint64)
    for bit in range(bits):
        for axis in range(3):
            codes |= ((q[:, axis] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(3 * bit + axis)
    return codes


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("source")
    parser.add_argument("target")
    parser.add_argument("order", choices=["random", "morton"])
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    grid = read(args.source)
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    connectivity = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).astype(np.int64)
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray()).astype(np.int64)
    types = vtk_to_numpy(grid.GetCellTypesArray())
    counts = np.diff(offsets)
    rng = np.random.default_rng(args.seed)

    if args.order == "random":
        cell_order = rng.permutation(len(types))
    else:
        cell_order = np.argsort(morton_codes(cell_centres(points, connectivity, offsets)), kind="stable")
    # The connectivity of the cells in their new order.
    lengths = counts[cell_order]
    new_offsets = np.concatenate(([0], np.cumsum(lengths)))
    gather = np.repeat(offsets[:-1][cell_order] - new_offsets[:-1], lengths) + np.arange(new_offsets[-1])
    new_connectivity = connectivity[gather]

    if args.order == "random":
        point_target = rng.permutation(len(points))
    else:  # by first use; unused points last
        used, first = np.unique(new_connectivity, return_index=True)
        by_use = used[np.argsort(first)]
        rest = np.setdiff1d(np.arange(len(points)), by_use)
        point_target = np.empty(len(points), np.int64)
        point_target[np.concatenate((by_use, rest))] = np.arange(len(points))
    new_points = np.empty_like(points)
    new_points[point_target] = points

    out = vtk.vtkUnstructuredGrid()
    vtk_points = vtk.vtkPoints()
    vtk_points.SetData(numpy_to_vtk(new_points, deep=1))
    out.SetPoints(vtk_points)
    cells = vtk.vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(new_offsets.astype(np.int64), deep=1),
                  numpy_to_vtkIdTypeArray(point_target[new_connectivity].astype(np.int64), deep=1))
    out.SetCells(numpy_to_vtk(types[cell_order].astype(np.uint8), deep=1, array_type=vtk.VTK_UNSIGNED_CHAR), cells)
    point_data = grid.GetPointData()
    for a in range(point_data.GetNumberOfArrays()):
        values = vtk_to_numpy(point_data.GetArray(a))
        moved = np.empty_like(values)
        moved[point_target] = values
        array = numpy_to_vtk(moved, deep=1)
        array.SetName(point_data.GetArrayName(a))
        out.GetPointData().AddArray(array)
    cell_data = grid.GetCellData()
    for a in range(cell_data.GetNumberOfArrays()):
        array = numpy_to_vtk(vtk_to_numpy(cell_data.GetArray(a))[cell_order], deep=1)
        array.SetName(cell_data.GetArrayName(a))
        out.GetCellData().AddArray(array)

    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetFileName(args.target)
    writer.SetInputData(out)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.Write()
    print(f"{args.target}: {len(types)} cells, {len(points)} points in {args.order} order")


if __name__ == "__main__":
    main()
