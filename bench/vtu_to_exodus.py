#!/usr/bin/python3
"""Writes a .vtu mesh (tets, hexes, wedges, pyramids) as an Exodus II file of STEPS time steps for
bench/exodus_convert.sh, with the test data's writer (tests/data/exodus/make_exodus_files.py:
the Exodus layout and node orders VTK's own reader is checked against there). Every point array
of the .vtu is a nodal variable; step s holds it times (1 + s/10), at time s.

usage: /usr/bin/python3 bench/vtu_to_exodus.py IN.vtu OUT.exo [STEPS=8] [FORMAT=NETCDF3_64BIT_OFFSET|NETCDF4]
(NETCDF4: zlib level 4, as SEACAS writes compressed files). Needs python3-vtk9 and python3-netcdf4.
"""
import os
import sys

import numpy as np
import vtk
from vtk.util import numpy_support

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "exodus"))
import make_exodus_files  # noqa: E402


def sorted_by_type(vtu):
    """The .vtu's mesh with its cells sorted by type (one Exodus block, or CGNS section, each)."""
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu)
    reader.Update()
    grid = reader.GetOutput()
    types = numpy_support.vtk_to_numpy(grid.GetCellTypesArray())
    order = np.argsort(types, kind="stable")
    if np.any(order != np.arange(len(order))):
        sorted_grid = vtk.vtkUnstructuredGrid()
        sorted_grid.SetPoints(grid.GetPoints())
        sorted_grid.GetPointData().ShallowCopy(grid.GetPointData())
        sorted_grid.Allocate(grid.GetNumberOfCells())
        for c in order:
            sorted_grid.InsertNextCell(grid.GetCellType(int(c)), grid.GetCell(int(c)).GetPointIds())
        grid = sorted_grid
    return grid


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    steps = int(sys.argv[3]) if len(sys.argv) > 3 else 8
    fmt = sys.argv[4] if len(sys.argv) > 4 else "NETCDF3_64BIT_OFFSET"
    grid = sorted_by_type(sys.argv[1])
    data = grid.GetPointData()
    arrays = {data.GetArrayName(i): numpy_support.vtk_to_numpy(data.GetArray(i)).astype(np.float64)
              for i in range(data.GetNumberOfArrays()) if data.GetArray(i).GetNumberOfComponents() == 1}
    values = lambda s: ({name: v * (1 + s / 10) for name, v in arrays.items()}, {})
    make_exodus_files.write_exodus(sys.argv[2], grid, values, [float(s) for s in range(steps)], fmt,
                                   compress=fmt == "NETCDF4")


if __name__ == "__main__":
    main()
