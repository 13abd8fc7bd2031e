import sys, vtk
src, base = sys.argv[1], sys.argv[2]
r = vtk.vtkXMLUnstructuredGridReader(); r.SetFileName(src)
w = vtk.vtkEnSightWriter(); w.SetInputConnection(r.GetOutputPort()); w.SetPath("/tmp/ensb"); w.SetBaseName(base)
w.Write(); w.WriteCaseFile(1)
