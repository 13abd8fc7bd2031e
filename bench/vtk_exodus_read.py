#!/usr/bin/python3
"""Seconds VTK's vtkExodusIIReader takes to read every time step of an Exodus file (all nodal and
element variables on; one Update per step, as ParaView reads a time series), from the reader's
creation to the last step's Update: bench/exodus_convert.sh's VTK figure.

usage: /usr/bin/python3 bench/vtk_exodus_read.py FILE.exo
"""
import sys
import time

import vtk

start = time.perf_counter()
reader = vtk.vtkExodusIIReader()
reader.SetFileName(sys.argv[1])
reader.UpdateInformation()
reader.SetAllArrayStatus(vtk.vtkExodusIIReader.NODAL, 1)
reader.SetAllArrayStatus(vtk.vtkExodusIIReader.ELEM_BLOCK, 1)
for step in range(reader.GetNumberOfTimeSteps()):
    reader.SetTimeStep(step)
    reader.Update()
print(f"{time.perf_counter() - start:.4f}")
