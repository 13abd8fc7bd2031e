"""Writes a .vtu mesh as an EnSight Gold case of two parts, for `--region` measurements
(bench/series_convert_paired.sh): part 1 the cells whose centre has x below SPLIT_X, part 2 the
rest, by VTK's own vtkEnSightWriter (C Binary; parts from a BlockId cell array), its point arrays
as per-node variables.

usage: /usr/bin/python3 bench/vtu_to_ensight_parts.py MESH.vtu OUT_DIR [SPLIT_X=0.85]
Writes OUT_DIR/parts.0.case and prints the two parts' cell counts.
"""
import os
import sys

import numpy as np
import vtk
from vtk.util import numpy_support


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    mesh, out = sys.argv[1], sys.argv[2]
    split_x = float(sys.argv[3]) if len(sys.argv) > 3 else 0.85
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(mesh)
    reader.Update()
    grid = reader.GetOutput()
    centres = vtk.vtkCellCenters()
    centres.SetInputData(grid)
    centres.Update()
    x = numpy_support.vtk_to_numpy(centres.GetOutput().GetPoints().GetData())[:, 0]
    block = np.where(x < split_x, 1, 2).astype(np.int32)
    ids = numpy_support.numpy_to_vtk(block, deep=1)
    ids.SetName("BlockId")
    grid.GetCellData().AddArray(ids)
    os.makedirs(out, exist_ok=True)
    writer = vtk.vtkEnSightWriter()
    writer.SetInputData(grid)
    writer.SetPath(out)
    writer.SetBaseName("parts")
    writer.Write()
    writer.WriteCaseFile(1)
    print(f"part 1: {(block == 1).sum()} cells, part 2: {(block == 2).sum()} cells")


if __name__ == "__main__":
    main()
