#!/usr/bin/python3
"""Writes a .vtu mesh as a ParaView file series of STEPS time steps, as OpenFOAM's foamToVTK
writes a case's times: OUT_DIR/step_S.vtu (VTK's own XML writer, appended raw data, so
polyhedra stay polyhedra) holding every point array of the .vtu times (1 + S/10), and
OUT_DIR/series.vtu.series naming them at times 0, 1, ... For the convert benchmarks of a series
on one mesh (bench/RESULTS.md).

usage: /usr/bin/python3 bench/vtu_series.py IN.vtu OUT_DIR [STEPS=8]   (python3-vtk9)
"""
import json
import os
import sys

import vtk
from vtk.util import numpy_support

if len(sys.argv) < 3:
    sys.exit(__doc__)
source, out = sys.argv[1], sys.argv[2]
steps = int(sys.argv[3]) if len(sys.argv) > 3 else 8
reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(source)
reader.Update()
grid = reader.GetOutput()
data = grid.GetPointData()
original = {data.GetArrayName(i): numpy_support.vtk_to_numpy(data.GetArray(i)).copy()
            for i in range(data.GetNumberOfArrays())}
os.makedirs(out, exist_ok=True)
files = []
for s in range(steps):
    for name, values in original.items():
        numpy_support.vtk_to_numpy(data.GetArray(name))[:] = values * (1 + s / 10)
        data.GetArray(name).Modified()
    name = f"step_{s}.vtu"
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetFileName(os.path.join(out, name))
    writer.SetInputData(grid)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.Write()
    files.append({"name": name, "time": float(s)})
with open(os.path.join(out, "series.vtu.series"), "w") as f:
    json.dump({"file-series-version": "1.0", "files": files}, f, indent=1)
print(f"{out}/series.vtu.series: {steps} steps of {grid.GetNumberOfCells()} cells")
