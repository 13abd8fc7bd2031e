# A check of VTK 9.1's Lagrange hexahedron node order (a Python model of volstream's lagrange_hex_node, umesh/quadratic.cpp) against the node positions vtkCellTypeSource gives, orders 1-6.
import vtk
def index(i, j, k, p):
    ib, jb, kb = i in (0, p), j in (0, p), k in (0, p)
    n = ib + jb + kb
    if n == 3:
        return ((2 if j else 1) if i else (3 if j else 0)) + (4 if k else 0)
    m = p - 1
    if n == 2:
        if not ib:
            edge, along = (2 if j else 0) + (4 if k else 0), i - 1
        elif not jb:
            edge, along = (1 if i else 3) + (4 if k else 0), j - 1
        else:
            edge, along = 8 + ((2 if j else 1) if i else (3 if j else 0)), k - 1
        return 8 + edge * m + along
    off = 8 + 12 * m
    if n == 1:
        if ib:
            face, a, b = (1 if i else 0), j, k
        elif jb:
            face, a, b = (3 if j else 2), i, k
        else:
            face, a, b = (5 if k else 4), i, j
        return off + face * m * m + (a - 1) + m * (b - 1)
    off += 6 * m * m
    return off + (i - 1) + m * ((j - 1) + m * (k - 1))
for p in range(1, 7):
    s = vtk.vtkCellTypeSource(); s.SetCellType(vtk.VTK_LAGRANGE_HEXAHEDRON); s.SetCellOrder(p); s.SetBlocksDimensions(1,1,1); s.Update()
    g = s.GetOutput(); c = g.GetCell(0)
    bad = 0
    for n in range(c.GetNumberOfPoints()):
        x = g.GetPoint(c.GetPointId(n))
        i, j, k = (round(v * p) for v in x)
        if index(i, j, k, p) != n: bad += 1
    print(p, c.GetNumberOfPoints(), "mismatches", bad)
