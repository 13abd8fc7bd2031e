#!/usr/bin/python3
"""Writes a .vtu mesh (tets, hexes, wedges, pyramids; with --polyhedra any cells, polyhedra
too) as a CGNS file of STEPS time steps for bench/solver_files_convert.sh, with the test data's
writer (tests/data/cgns/make_cgns_files.py: the layout and node orders VTK's own CGNS reader is
checked against there): one unstructured zone, a section per cell type (with --polyhedra, every
cell an NFACE_n polyhedron of NGON_n faces, as Fluent and STAR-CCM+ write them), a Vertex
solution per step holding every point array of the .vtu times (1 + s/10), at time s.

usage: /usr/bin/python3 bench/vtu_to_cgns.py IN.vtu OUT.cgns [STEPS=8] [--polyhedra]
       (python3-vtk9, libcgns-dev)
"""
import os
import sys

import numpy as np
import vtk
from vtk.util import numpy_support

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "data", "cgns"))
sys.path.insert(0, os.path.join(HERE, "..", "tests", "data", "exodus"))
import make_cgns_files  # noqa: E402
import vtu_to_exodus  # noqa: E402

polyhedra = "--polyhedra" in sys.argv
args = [a for a in sys.argv[1:] if a != "--polyhedra"]
if len(args) < 2:
    sys.exit(__doc__)
steps = int(args[2]) if len(args) > 2 else 8
grid = make_cgns_files.read_vtu(args[0]) if polyhedra else vtu_to_exodus.sorted_by_type(args[0])
data = grid.GetPointData()
arrays = {data.GetArrayName(i): numpy_support.vtk_to_numpy(data.GetArray(i)).astype(np.float64)
          for i in range(data.GetNumberOfArrays()) if data.GetArray(i).GetNumberOfComponents() == 1}
make_cgns_files.write_time_series(args[1], grid, lambda s: {n: v * (1 + s / 10) for n, v in arrays.items()},
                                  [float(s) for s in range(steps)], polyhedra)
