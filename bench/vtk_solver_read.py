#!/usr/bin/python3
"""Seconds VTK takes to read every time step of an Exodus II or CGNS file with its own reader
(vtkExodusIIReader, vtkCGNSReader; all point and cell arrays on; one update per step, as ParaView
plays a series), from the reader's creation to the last step's update:
bench/solver_files_convert.sh's VTK figure.

usage: /usr/bin/python3 bench/vtk_solver_read.py FILE.exo|FILE.cgns
"""
import sys
import time

import vtk

start = time.perf_counter()
if sys.argv[1].endswith(".cgns"):
    reader = vtk.vtkCGNSReader()
    reader.SetFileName(sys.argv[1])
    reader.UpdateInformation()
    reader.EnableAllPointArrays()
    reader.EnableAllCellArrays()
    times = reader.GetOutputInformation(0).Get(vtk.vtkStreamingDemandDrivenPipeline.TIME_STEPS()) or [0.0]
    for t in times:
        reader.UpdateTimeStep(t)
else:
    reader = vtk.vtkExodusIIReader()
    reader.SetFileName(sys.argv[1])
    reader.UpdateInformation()
    reader.SetAllArrayStatus(vtk.vtkExodusIIReader.NODAL, 1)
    reader.SetAllArrayStatus(vtk.vtkExodusIIReader.ELEM_BLOCK, 1)
    for step in range(reader.GetNumberOfTimeSteps()):
        reader.SetTimeStep(step)
        reader.Update()
print(f"{time.perf_counter() - start:.4f}")
