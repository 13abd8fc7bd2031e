# A check of VTK 9.1's Lagrange tetra node order (a Python model of volstream's tetra_lattice, umesh/quadratic.cpp; faces 0-1-3, 2-3-1, 0-3-2, 0-2-1 found from VTK's order-4 and 5 nodes) against vtkCellTypeSource, orders 1-9.
import vtk, itertools
import numpy as np
def tri_order(A, B, C, m):
    """points (as barycentric-lattice vectors) of a triangle of order m with vertex lattice points A,B,C (numpy int arrays scaled so that edges have m steps), VTK recursive ordering"""
    if m < 0: return []
    if m == 0: return [A]
    pts = [A, B, C]
    for (a, b) in ((A, B), (B, C), (C, A)):
        for t in range(1, m):
            pts.append(a + (b - a) * t // m)
    if m >= 3:
        # interior: triangle of order m-3, vertices moved inward one step
        step_ab = (B - A) // m; step_ac = (C - A) // m; step_bc = (C - B) // m
        A2 = A + step_ab + step_ac; B2 = B - step_ab + step_bc; C2 = C - step_ac - step_bc
        pts += tri_order(A2, B2, C2, m - 3)
    return pts
def tet_order(V, p, faces):
    if p < 0: return []
    if p == 0: return [V[0]]
    pts = list(V)
    for a, b in ((0,1),(1,2),(2,0),(0,3),(1,3),(2,3)):
        for t in range(1, p):
            pts.append(V[a] + (V[b] - V[a]) * t // p)
    if p >= 3:
        for f in faces:
            A, B, C = V[f[0]], V[f[1]], V[f[2]]
            sab = (B - A) // p; sac = (C - A) // p; sbc = (C - B) // p
            pts += tri_order(A + sab + sac, B - sab + sbc, C - sac - sbc, p - 3)
    if p >= 4:
        s = [(V[b] - V[a]) // p for a, b in ((0,1),(0,2),(0,3))]
        # interior vertices: each vertex moved one step toward the centroid
        c = [V[0] + s[0] + s[1] + s[2], V[1] - s[0] + (V[2]-V[1])//p + (V[3]-V[1])//p,
             V[2] - s[1] + (V[1]-V[2])//p + (V[3]-V[2])//p, V[3] - s[2] + (V[1]-V[3])//p + (V[2]-V[3])//p]
        pts += tet_order(c, p - 4, faces)
    return pts
def vtk_positions(p):
    s = vtk.vtkCellTypeSource(); s.SetCellType(vtk.VTK_LAGRANGE_TETRAHEDRON); s.SetCellOrder(p); s.SetBlocksDimensions(1,1,1); s.Update()
    g = s.GetOutput(); c = g.GetCell(0)
    X = np.array([g.GetPoint(c.GetPointId(n)) for n in range(c.GetNumberOfPoints())])
    return X
for faces in ([(0,1,3),(2,3,1),(0,3,2),(0,2,1)],):
    ok = True
    for p in range(1, 10):
        X = vtk_positions(p)
        # express in the cell's own corner frame: barycentric lattice via corners
        V0, V1, V2, V3 = X[0], X[1], X[2], X[3]
        M = np.array([V1 - V0, V2 - V0, V3 - V0]).T
        lat = [tuple(np.rint(np.linalg.solve(M, x - V0) * p).astype(int)) for x in X]
        V = [np.array(v) * p for v in ((0,0,0),(1,0,0),(0,1,0),(0,0,1))]
        mine = [tuple(int(c) for c in v) for v in tet_order([v.copy() for v in V], p, faces)]
        # scale: my points are in units of 1 (V scaled by p, steps of 1)
        if mine != lat:
            ok = False
            bad = [n for n in range(len(lat)) if n >= len(mine) or mine[n] != lat[n]]
            print(faces, "order", p, "first mismatch", bad[:5], len(mine), len(lat))
            break
    if ok: print("MATCH", faces)
