import sys, time, vtk
for case in sys.argv[1:]:
    for i in range(3):
        t0 = time.perf_counter()
        r = vtk.vtkGenericEnSightReader(); r.SetCaseFileName(case); r.ReadAllVariablesOn(); r.Update()
        t1 = time.perf_counter()
        b = r.GetOutput().GetBlock(0)
        print(f"VTK {vtk.vtkVersion.GetVTKVersion()} vtkGenericEnSightReader {case}: {t1 - t0:.3f} s, {b.GetNumberOfCells()} cells")
