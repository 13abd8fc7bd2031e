"""Writes the Exodus II files of this directory from the format's description (the NetCDF
dimensions and variables SEACAS's Exodus library writes; node orders from its Ioss element
tables), with Debian's python3-netcdf4, from meshes VTK made; and beside each, as .vtu (VTK's
own writer), the mesh and values the reader must give (tests/io/exodus_test.cpp).

Then reads every .exo back with VTK's own vtkExodusIIReader and stops unless VTK finds the
same nodes at the same places in every element and the same values: so the node orders (VTK's
to Exodus's, the reverse of what volstream's reader does) are checked against VTK's reader.

Run from this directory: /usr/bin/python3 make_exodus_files.py (python3-vtk9 and
python3-netcdf4; the committed files come from VTK 9.1.0 and netCDF 4.9.0).
- exodus_mixed.exo (64-bit offset): VTK's cell sources' tets, hexes, wedges and pyramids,
  warped, one element block each, and a block of SHELL4 faces the reader leaves out; three
  time steps of nodal f (linear), g, vel_x/vel_y/vel_z (one vector) and element cell_id and
  pressure. exodus_mixed_1.vtu: its step 1.
- exodus_quadratic.exo (NetCDF-4, zlib): the quadratic cells of ../vtu/vtk_quadratic.vtu that
  Exodus has (HEX20, HEX27, TETRA10, WEDGE15, PYRAMID13); exodus_quadratic.vtu the same.
- exodus_mixed.exo.2.0 and .2.1: exodus_mixed as two ranks of a parallel run write it (every
  other element of each block on each, on its own nodes: the ranks share nodes everywhere).
- damaged_hdf5.exo is not written here: it is the committed exodus_quadratic.exo with byte 27151
  set to '0' (a fuzzer's find, on which HDF5 frees an uninitialised pointer; HDF5 files are not
  byte for byte the same when written again).
- exodus_old.exo (classic): exodus_mixed's mesh as old writers wrote it (one `coord` variable,
  all nodal variables in one `vals_nod_var`), one step; its values are exodus_mixed's step 0.
"""
import math
import os

import netCDF4
import numpy as np
import vtk
from vtk.util import numpy_support

HERE = os.path.dirname(os.path.abspath(__file__))

# For each VTK type: the Exodus type and, for each Exodus node, the VTK node that is it.
EXODUS = {
    vtk.VTK_TETRA: ("TETRA", None),
    vtk.VTK_HEXAHEDRON: ("HEX8", None),
    vtk.VTK_WEDGE: ("WEDGE6", [0, 2, 1, 3, 5, 4]),
    vtk.VTK_PYRAMID: ("PYRAMID5", None),
    vtk.VTK_QUADRATIC_TETRA: ("TETRA10", None),
    vtk.VTK_QUADRATIC_HEXAHEDRON: ("HEX20", list(range(12)) + [16, 17, 18, 19, 12, 13, 14, 15]),
    vtk.VTK_TRIQUADRATIC_HEXAHEDRON: ("HEX27", list(range(12)) + [16, 17, 18, 19, 12, 13, 14, 15,
                                                                  26, 24, 25, 20, 21, 22, 23]),
    vtk.VTK_QUADRATIC_WEDGE: ("WEDGE15", [0, 2, 1, 3, 5, 4, 8, 7, 6, 12, 14, 13, 11, 10, 9]),
    vtk.VTK_QUADRATIC_PYRAMID: ("PYRAMID13", None),
}


def mixed_grid():
    """Tets, hexes, wedges and pyramids of VTK's cell source (2x2x2 blocks each), side by side
    along x, warped smoothly; cells in that order (one Exodus block per type)."""
    append = vtk.vtkAppendFilter()
    for i, cell_type in enumerate((vtk.VTK_TETRA, vtk.VTK_HEXAHEDRON, vtk.VTK_WEDGE, vtk.VTK_PYRAMID)):
        source = vtk.vtkCellTypeSource()
        source.SetCellType(cell_type)
        source.SetBlocksDimensions(2, 2, 2)
        source.Update()
        move = vtk.vtkTransform()
        move.Translate(2.5 * i, 0, 0)
        moved = vtk.vtkTransformFilter()
        moved.SetTransform(move)
        moved.SetInputData(source.GetOutput())
        moved.Update()
        append.AddInputData(moved.GetOutput())
    append.Update()
    grid = append.GetOutput()
    points = grid.GetPoints()
    for p in range(points.GetNumberOfPoints()):
        x, y, z = points.GetPoint(p)
        points.SetPoint(p, (x + 0.1 * math.sin(y), y + 0.08 * z * z, z + 0.05 * x))
    return grid


def nodal_values(grid, step):
    xyz = numpy_support.vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    x, y, z = xyz[:, 0], xyz[:, 1], xyz[:, 2]
    return {"f": 1 + 2 * x + 3 * y + 4 * z, "g": (1 + step) * (x * y + z * z) + step,
            "vel_x": y * (1 + step), "vel_y": -x, "vel_z": 0.5 + step + 0 * x}


def element_values(grid, step):
    n = grid.GetNumberOfCells()
    return {"cell_id": np.arange(n, dtype=np.float64), "pressure": 100.0 + step * np.arange(n) % 7}


def blocks_of(grid):
    """Runs of cells of one type, in order: [(vtk type, [cell ids])]."""
    blocks = []
    for c in range(grid.GetNumberOfCells()):
        t = grid.GetCellType(c)
        if not blocks or blocks[-1][0] != t:
            blocks.append((t, []))
        blocks[-1][1].append(c)
    return blocks


def write_exodus(name, grid, steps, times, fmt, old_layout=False, shells=None, compress=False):
    """`grid` as an Exodus II file: `steps` (a function of the step) of nodal and element values."""
    nc = netCDF4.Dataset(name, "w", format=fmt)
    nc.api_version = np.float32(8.03)
    nc.version = np.float32(8.03)
    nc.floating_point_word_size = np.int32(8)
    nc.file_size = np.int32(0 if old_layout else 1)  # the Exodus library picks the layout by it
    nc.title = "volstream test mesh (make_exodus_files.py)"
    n = grid.GetNumberOfPoints()
    blocks = blocks_of(grid)
    if shells:
        blocks.append(("SHELL4", shells))
    nc.createDimension("len_string", 33)
    nc.createDimension("len_line", 81)
    nc.createDimension("four", 4)
    nc.createDimension("len_name", 33)
    nc.createDimension("time_step", None)
    nc.createDimension("num_dim", 3)
    nc.createDimension("num_nodes", n)
    nc.createDimension("num_elem", sum(len(b[1]) for b in blocks))
    nc.createDimension("num_el_blk", len(blocks))
    kw = {"zlib": True, "complevel": 4} if compress else {}
    xyz = numpy_support.vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)
    if old_layout:
        coord = nc.createVariable("coord", "f8", ("num_dim", "num_nodes"), **kw)
        coord[:] = xyz.T
    else:
        for a, axis in enumerate("xyz"):
            nc.createVariable("coord" + axis, "f8", ("num_nodes",), **kw)[:] = xyz[:, a]
    ids = nc.createVariable("eb_prop1", "i4", ("num_el_blk",))
    ids.setncattr("name", "ID")
    ids[:] = [10 * (b + 1) for b in range(len(blocks))]
    nc.createVariable("eb_status", "i4", ("num_el_blk",))[:] = 1
    for b, (cell_type, cells) in enumerate(blocks, start=1):
        if cell_type == "SHELL4":
            exodus_type, conn = "SHELL4", np.array(cells)
        else:
            exodus_type, order = EXODUS[cell_type]
            conn = []
            for c in cells:
                ids_of = grid.GetCell(c).GetPointIds()
                vtk_nodes = [ids_of.GetId(k) for k in range(ids_of.GetNumberOfIds())]
                conn.append([vtk_nodes[k] for k in (order or range(len(vtk_nodes)))])
            conn = np.array(conn)
        nc.createDimension(f"num_el_in_blk{b}", conn.shape[0])
        nc.createDimension(f"num_nod_per_el{b}", conn.shape[1])
        v = nc.createVariable(f"connect{b}", "i4", (f"num_el_in_blk{b}", f"num_nod_per_el{b}"), **kw)
        v.elem_type = exodus_type
        v[:] = conn + 1
    nodal_names = list(steps(0)[0].keys())
    element_names = list(steps(0)[1].keys())
    for var, names in (("name_nod_var", nodal_names), ("name_elem_var", element_names)):
        if not names:  # a dimension of length 0 would be the record dimension
            continue
        nc.createDimension(var.replace("name_", "num_"), len(names))
        v = nc.createVariable(var, "S1", (var.replace("name_", "num_"), "len_name"))
        v[:] = netCDF4.stringtochar(np.array(names, dtype="S33"))
    nc.createVariable("time_whole", "f8", ("time_step",))[:] = times
    if old_layout:
        nodal = nc.createVariable("vals_nod_var", "f8", ("time_step", "num_nod_var", "num_nodes"), **kw)
    for s in range(len(times)):
        point_values, cell_values = steps(s)
        for k, name in enumerate(nodal_names):
            if old_layout:
                nodal[s, k, :] = point_values[name]
                continue
            if s == 0:
                nc.createVariable(f"vals_nod_var{k + 1}", "f8", ("time_step", "num_nodes"), **kw)
            nc.variables[f"vals_nod_var{k + 1}"][s, :] = point_values[name]
        for k, name in enumerate(element_names):
            for b, (cell_type, cells) in enumerate(blocks, start=1):
                if cell_type == "SHELL4":
                    continue
                var = f"vals_elem_var{k + 1}eb{b}"
                if s == 0:
                    nc.createVariable(var, "f8", ("time_step", f"num_el_in_blk{b}"), **kw)
                nc.variables[var][s, :] = cell_values[name][cells]
    nc.close()


def with_values(grid, point_values, cell_values):
    out = vtk.vtkUnstructuredGrid()
    out.DeepCopy(grid)
    for data, values in ((out.GetPointData(), point_values), (out.GetCellData(), cell_values)):
        for name, v in values.items():
            a = numpy_support.numpy_to_vtk(np.ascontiguousarray(v, dtype=np.float64), deep=True)
            a.SetName(name)
            data.AddArray(a)
    return out


def write_vtu(grid, name):
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetInputData(grid)
    writer.SetFileName(name)
    writer.SetDataModeToAscii()
    writer.Write()


# VTK's Exodus reader keeps an Exodus wedge's nodes in their order, so its wedges are the mirror
# images of VTK's own (VTK's first triangle faces away from the second, Exodus's towards it;
# the field is the same): VTK's node k of a wedge there is node VTK_READER_WEDGE[k] of ours.
VTK_READER_WEDGE = {vtk.VTK_WEDGE: [0, 2, 1, 3, 5, 4],
                    vtk.VTK_QUADRATIC_WEDGE: [0, 2, 1, 3, 5, 4, 8, 7, 6, 11, 10, 9, 12, 14, 13]}


def vtk_array(data, name):
    """VTK's array of the Exodus variable `name` and the component: VTK joins NAME_x, NAME_y,
    NAME_z into the vector NAME_ (VTK 9.1 keeps the underscore)."""
    if data.GetArray(name):
        return data.GetArray(name), 0
    return data.GetArray(name[:-1]), "xyz".index(name[-1])


def check_with_vtk(name, grid, step, point_values, cell_values):
    """VTK's Exodus reader must see `grid`'s elements (node places, in VTK's order) and values."""
    reader = vtk.vtkExodusIIReader()
    reader.SetFileName(name)
    reader.UpdateInformation()
    reader.SetAllArrayStatus(vtk.vtkExodusIIReader.NODAL, 1)
    reader.SetAllArrayStatus(vtk.vtkExodusIIReader.ELEM_BLOCK, 1)
    reader.SetTimeStep(step)
    reader.Update()
    iterate = reader.GetOutput().NewIterator()
    iterate.InitTraversal()
    cell = 0
    while not iterate.IsDoneWithTraversal():
        block = iterate.GetCurrentDataObject()
        iterate.GoToNextItem()
        if block.GetCellType(0) == vtk.VTK_QUAD:
            continue
        nodal = {n: vtk_array(block.GetPointData(), n) for n in point_values}
        for c in range(block.GetNumberOfCells()):
            mine, theirs = grid.GetCell(cell), block.GetCell(c)
            assert mine.GetCellType() == theirs.GetCellType(), (name, cell)
            mirror = VTK_READER_WEDGE.get(mine.GetCellType(), range(mine.GetNumberOfPoints()))
            for k in range(mine.GetNumberOfPoints()):
                a = np.array(mine.GetPoints().GetPoint(mirror[k]))
                b = np.array(theirs.GetPoints().GetPoint(k))
                assert np.allclose(a, b, atol=1e-6), (name, "cell", cell, "node", k, a, b)
                for n, array in nodal.items():
                    want = point_values[n][mine.GetPointId(mirror[k])]
                    array, component = array
                    got = array.GetComponent(theirs.GetPointId(k), component)
                    assert abs(got - want) <= 1e-12 * (1 + abs(want)), (name, n, got, want)
            for n, values in cell_values.items():
                got = block.GetCellData().GetArray(n).GetValue(c)
                assert got == values[cell], (name, n, cell, got, values[cell])
            cell += 1
    assert cell == grid.GetNumberOfCells(), (name, cell)
    print(f"{name}: VTK's Exodus reader sees the same {cell} elements and values at step {step}")


def write_rank_file(grid, rank, ranks, steps, times):
    """Rank `rank` of `ranks` as a parallel run writes it (exodus_mixed.exo.2.0, ...): every
    ranks-th element of each block, on its own nodes (numbered in first use), so that the ranks
    share nodes everywhere; its values are the whole mesh's."""
    cells = vtk.vtkIdList()
    for c in range(rank, grid.GetNumberOfCells(), ranks):
        cells.InsertNextId(c)
    extract = vtk.vtkExtractCells()
    extract.SetInputData(grid)
    extract.SetCellList(cells)
    extract.Update()
    piece = vtk.vtkUnstructuredGrid()
    piece.DeepCopy(extract.GetOutput())
    ids = [cells.GetId(k) for k in range(cells.GetNumberOfIds())]
    name = f"exodus_mixed.exo.{ranks}.{rank}"

    def piece_steps(s):
        point_values, cell_values = nodal_values(piece, s), steps(s)[1]
        return point_values, {n: v[ids] for n, v in cell_values.items()}
    write_exodus(name, piece, piece_steps, times, "NETCDF3_64BIT_OFFSET")
    for s in range(len(times)):
        check_with_vtk(name, piece, s, *piece_steps(s))


def quadratic_subset():
    """The cells of ../vtu/vtk_quadratic.vtu that Exodus (and CGNS) have, with their f, g, cell_id."""
    source = vtk.vtkXMLUnstructuredGridReader()
    source.SetFileName(os.path.join(HERE, "..", "vtu", "vtk_quadratic.vtu"))
    source.Update()
    full = source.GetOutput()
    keep = vtk.vtkIdList()
    for c in range(full.GetNumberOfCells()):
        if full.GetCellType(c) in EXODUS:
            keep.InsertNextId(c)
    extract = vtk.vtkExtractCells()
    extract.SetInputData(full)
    extract.SetCellList(keep)
    extract.Update()
    quadratic = vtk.vtkUnstructuredGrid()
    quadratic.SetPoints(extract.GetOutput().GetPoints())
    quadratic.Allocate()
    for c in range(extract.GetOutput().GetNumberOfCells()):
        cell = extract.GetOutput().GetCell(c)
        quadratic.InsertNextCell(cell.GetCellType(), cell.GetPointIds())
    g = numpy_support.vtk_to_numpy(extract.GetOutput().GetPointData().GetArray("g")).astype(np.float64)
    f = numpy_support.vtk_to_numpy(extract.GetOutput().GetPointData().GetArray("f")).astype(np.float64)
    cell_id = numpy_support.vtk_to_numpy(extract.GetOutput().GetCellData().GetArray("cell_id")).astype(np.float64)
    return quadratic, f, g, cell_id


def main():
    mixed = mixed_grid()
    bottom = [c for c in range(mixed.GetNumberOfCells()) if mixed.GetCellType(c) == vtk.VTK_HEXAHEDRON][:4]
    shells = [[mixed.GetCell(c).GetPointId(k) for k in range(4)] for c in bottom]
    times = [0.0, 0.5, 1.25]
    steps = lambda s: (nodal_values(mixed, s), element_values(mixed, s))
    write_exodus("exodus_mixed.exo", mixed, steps, times, "NETCDF3_64BIT_OFFSET", shells=shells)
    write_vtu(with_values(mixed, *steps(1)), "exodus_mixed_1.vtu")
    write_exodus("exodus_old.exo", mixed, steps, times[:1], "NETCDF3_CLASSIC", old_layout=True)
    for s in range(3):
        check_with_vtk("exodus_mixed.exo", mixed, s, *steps(s))
    check_with_vtk("exodus_old.exo", mixed, 0, *steps(0))
    for rank in range(2):
        write_rank_file(mixed, rank, 2, steps, times)


    quadratic, f, g, cell_id = quadratic_subset()
    quadratic_steps = lambda s: ({"f": f, "g": g}, {"cell_id": cell_id})
    assert [b[0] for b in blocks_of(quadratic)] == sorted(set(quadratic.GetCellType(c) for c in
                                                               range(quadratic.GetNumberOfCells())),
                                                           key=[quadratic.GetCellType(c) for c in
                                                                range(quadratic.GetNumberOfCells())].index)
    write_exodus("exodus_quadratic.exo", quadratic, quadratic_steps, [0.0], "NETCDF4", compress=True)
    write_vtu(with_values(quadratic, *quadratic_steps(0)), "exodus_quadratic.vtu")
    check_with_vtk("exodus_quadratic.exo", quadratic, 0, *quadratic_steps(0))


if __name__ == "__main__":
    main()
