# Time vtkOpenFOAMReader reading a case's internal mesh and cell fields (all time steps), median of 3.
import sys, time, statistics, vtk
case = sys.argv[1]
decompose = len(sys.argv) > 2 and sys.argv[2] == "decompose"
ts = []
for i in range(3):
    t0 = time.perf_counter()
    r = vtk.vtkOpenFOAMReader()
    r.SetFileName(case)
    r.CreateCellToPointOff()
    if decompose: r.DecomposePolyhedraOn()
    else: r.DecomposePolyhedraOff()
    r.UpdateInformation()
    times = r.GetTimeValues()
    n = 0
    for k in range(times.GetNumberOfTuples()):
        r.UpdateTimeStep(times.GetValue(k)); r.Update()
        n = r.GetOutput().GetBlock(0).GetNumberOfCells()
    ts.append(time.perf_counter() - t0)
    print("run", i, ts[-1], "s", n, "cells", times.GetNumberOfTuples(), "steps", flush=True)
print("median", statistics.median(ts))
