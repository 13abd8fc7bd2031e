#!/usr/bin/python3
"""Seconds VTK's own OpenFOAM reader (vtkOpenFOAMReader, what ParaView opens a case with) takes
to read a case's internal mesh and cell fields at every time step, polyhedra kept whole (or
split with `decompose`), no cell-to-point data: three rounds, each from the reader's creation
to the last step's update; prints each round and the median. The VTK figure beside
`volstream convert CASE` in bench/RESULTS.md.

usage: /usr/bin/python3 bench/vtk_openfoam_read.py CASE/CASE.foam [decompose]   (python3-vtk9)
"""
import statistics
import sys
import time

import vtk

if len(sys.argv) < 2:
    sys.exit(__doc__)
seconds = []
for round_ in range(3):
    start = time.perf_counter()
    reader = vtk.vtkOpenFOAMReader()
    reader.SetFileName(sys.argv[1])
    reader.CreateCellToPointOff()
    reader.SetDecomposePolyhedra(len(sys.argv) > 2 and sys.argv[2] == "decompose")
    reader.UpdateInformation()
    times = reader.GetTimeValues()
    for k in range(times.GetNumberOfTuples()):
        reader.UpdateTimeStep(times.GetValue(k))
        reader.Update()
    cells = reader.GetOutput().GetBlock(0).GetNumberOfCells()
    seconds.append(time.perf_counter() - start)
    print(f"round {round_}: {seconds[-1]:.3f} s, {cells} cells, {times.GetNumberOfTuples()} steps", flush=True)
print(f"median {statistics.median(seconds):.3f}")
