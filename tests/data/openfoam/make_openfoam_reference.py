"""VTK's own OpenFOAM reader (vtkOpenFOAMReader) on each test case of this directory: its
internal mesh at the last time step, polyhedra not decomposed, cell values only (no
cell-to-point interpolation); the three the same, written as reference.vtu (zlib-compressed
binary) for tests/io/openfoam_test.cpp. Run by make_openfoam_files.sh; usage: python3 THIS DIR."""
import sys
import os
import vtk

here = sys.argv[1]
for case in ("box_ascii", "box_binary", "box_gz"):
    r = vtk.vtkOpenFOAMReader()
    r.SetFileName(os.path.join(here, case, case + ".foam"))
    r.DecomposePolyhedraOff()
    r.CreateCellToPointOff()
    r.UpdateInformation()
    times = r.GetTimeValues()
    last = times.GetValue(times.GetNumberOfTuples() - 1)
    r.UpdateTimeStep(last)
    r.Update()
    mesh = r.GetOutput().GetBlock(0)  # internalMesh
    assert isinstance(mesh, vtk.vtkUnstructuredGrid), type(mesh)
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetInputData(mesh)
    w.SetDataModeToAscii()
    w.WriteToOutputStringOn()
    w.Write()
    text = w.GetOutputString()
    if case == "box_ascii":
        first = text
        w = vtk.vtkXMLUnstructuredGridWriter()
        w.SetFileName(os.path.join(here, "reference.vtu"))
        w.SetInputData(mesh)
        w.SetDataModeToBinary()
        w.SetCompressorTypeToZLib()
        w.Write()
    else:
        assert text == first, case + " reads other than box_ascii in VTK"
    names = sorted(mesh.GetCellData().GetArrayName(i) for i in range(mesh.GetCellData().GetNumberOfArrays()))
    print(case, "time", last, mesh.GetNumberOfCells(), "cells", mesh.GetNumberOfPoints(), "points", names)
