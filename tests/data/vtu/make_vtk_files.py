"""Writes the vtk_* files of this directory (.vtu, .pvtu, .vtm and vtk_blocks/; and
../vtk/vtk_voxels.vtk) with VTK's own writers, so that
the reader is tested against files it did not write itself (tests/io/vtu_test.cpp).

Run from this directory with Debian's python3-vtk9: /usr/bin/python3 make_vtk_files.py
(the committed files come from VTK 9.1.0). The mesh: VTK's analytic "wavelet" on a 4x4x4 point
grid, split into 135 tets by vtkDataSetTriangleFilter, with its point scalar RTData.
"""
import vtk


def cell_type_source(cell_type, order):
    """A unit cube of cells of `cell_type` and `order` as vtkCellTypeSource makes them."""
    source = vtk.vtkCellTypeSource()
    source.SetCellType(cell_type)
    source.SetCellOrder(order)
    source.SetBlocksDimensions(1, 1, 1)
    source.Update()
    return source.GetOutput()


def write_xml(grid, name, ascii=False):
    """`grid` as a .vtu, ascii or appended raw."""
    xml = vtk.vtkXMLUnstructuredGridWriter()
    xml.SetInputData(grid)
    xml.SetFileName(name)
    if ascii:
        xml.SetDataModeToAscii()
    else:
        xml.SetDataModeToAppended()
        xml.EncodeAppendedDataOff()
    xml.Write()


def tets():
    source = vtk.vtkRTAnalyticSource()
    source.SetWholeExtent(0, 3, 0, 3, 0, 3)
    split = vtk.vtkDataSetTriangleFilter()
    split.SetInputConnection(source.GetOutputPort())
    return split


def write_compressed(mesh):
    """The whole mesh, appended raw, in blocks of 512 bytes of each of VTK's compressors."""
    for name, choose in (("zlib", "SetCompressorTypeToZLib"), ("lz4", "SetCompressorTypeToLZ4"),
                         ("lzma", "SetCompressorTypeToLZMA")):
        writer = vtk.vtkXMLUnstructuredGridWriter()
        writer.SetInputConnection(mesh.GetOutputPort())
        writer.SetFileName(f"vtk_{name}.vtu")
        getattr(writer, choose)()
        writer.SetDataModeToAppended()
        writer.EncodeAppendedDataOff()
        writer.SetBlockSize(512)
        writer.Write()


def write_pieces(mesh):
    """Three pieces as a parallel run writes them: ascii without ghosts (vtk_pieces.pvtu) and
    inline base64 + zlib with a layer of ghost cells (vtk_ghosts.pvtu, vtkGhostType arrays)."""
    for ghost_level, name, mode in ((0, "pieces", "SetDataModeToAscii"), (1, "ghosts", "SetDataModeToBinary")):
        writer = vtk.vtkXMLPUnstructuredGridWriter()
        writer.SetInputConnection(mesh.GetOutputPort())
        writer.SetFileName(f"vtk_{name}.pvtu")
        writer.SetNumberOfPieces(3)
        writer.SetStartPiece(0)
        writer.SetEndPiece(2)
        writer.SetGhostLevel(ghost_level)
        getattr(writer, mode)()
        writer.Write()


def write_blocks():
    """A multiblock as CFD writers leave one (vtk_blocks.vtm, ascii): the tets as two zones (cells
    0-67 and 68-134, each with VTK's vtkOriginalCellIds) and the surface as a boundary block.
    A pipeline of its own: the parallel writers' last request (one piece with ghosts) stays in
    the other's output."""
    mesh = tets()
    mesh.Update()
    whole = mesh.GetOutput()
    blocks = vtk.vtkMultiBlockDataSet()
    for index, (first, end) in enumerate(((0, 68), (68, 135))):
        cells = vtk.vtkIdList()
        for cell in range(first, end):
            cells.InsertNextId(cell)
        zone = vtk.vtkExtractCells()
        zone.SetInputData(whole)
        zone.SetCellList(cells)
        zone.Update()
        blocks.SetBlock(index, zone.GetOutput())
        blocks.GetMetaData(index).Set(vtk.vtkCompositeDataSet.NAME(), f"zone_{index}")
    surface = vtk.vtkDataSetSurfaceFilter()
    surface.SetInputData(whole)
    surface.Update()
    boundary = vtk.vtkMultiBlockDataSet()
    boundary.SetBlock(0, surface.GetOutput())
    boundary.GetMetaData(0).Set(vtk.vtkCompositeDataSet.NAME(), "walls")
    blocks.SetBlock(2, boundary)
    blocks.GetMetaData(2).Set(vtk.vtkCompositeDataSet.NAME(), "boundary")
    writer = vtk.vtkXMLMultiBlockDataWriter()
    writer.SetInputData(blocks)
    writer.SetFileName("vtk_blocks.vtm")
    writer.SetDataModeToAscii()
    writer.Write()


def write_voxels():
    """The wavelet's 27 cells as VTK's voxels (type 11), as ParaView writes image data it turned
    unstructured (a threshold, vtkAppendFilter): vtk_voxels.vtu (ascii) and, in legacy form,
    ../vtk/vtk_voxels.vtk (ascii, file version 5.1)."""
    source = vtk.vtkRTAnalyticSource()
    source.SetWholeExtent(0, 3, 0, 3, 0, 3)
    grid = vtk.vtkAppendFilter()
    grid.SetInputConnection(source.GetOutputPort())
    xml = vtk.vtkXMLUnstructuredGridWriter()
    xml.SetInputConnection(grid.GetOutputPort())
    xml.SetFileName("vtk_voxels.vtu")
    xml.SetDataModeToAscii()
    xml.Write()
    legacy = vtk.vtkUnstructuredGridWriter()
    legacy.SetInputConnection(grid.GetOutputPort())
    legacy.SetFileName("../vtk/vtk_voxels.vtk")
    legacy.Write()


def add_test_arrays(grid, g):
    """Point arrays f = 1 + 2x + 3y + 4z (linear) and g (a formula of x, y, z) at the grid's
    points, and a cell array cell_id = 0, 1, 2, ..."""
    points = grid.GetPoints()
    for name, formula in (("f", lambda x, y, z: 1 + 2 * x + 3 * y + 4 * z), ("g", g)):
        values = vtk.vtkDoubleArray()
        values.SetName(name)
        for i in range(points.GetNumberOfPoints()):
            values.InsertNextValue(formula(*points.GetPoint(i)))
        grid.GetPointData().AddArray(values)
    cell_id = vtk.vtkIntArray()
    cell_id.SetName("cell_id")
    for c in range(grid.GetNumberOfCells()):
        cell_id.InsertNextValue(c)
    grid.GetCellData().AddArray(cell_id)


def polyhedra_mesh():
    """Polyhedra (type 42) as OpenFOAM's foamToVTK writes them, with hexes beside them: a cube
    [0,2]^3 whose face x = 2 is split into four quads to meet the eight hexes of [2,4]x[0,2]^2
    (a 2:1 refinement step), a square pyramid on its face x = 0, and apart from both a hexagonal
    prism (two six-vertex faces). Point arrays f = 1 + 2x + 3y + 4z (linear) and g = xy + z^2, a
    cell array cell_id."""
    grid = vtk.vtkUnstructuredGrid()
    points = vtk.vtkPoints()
    index = {}

    def point(p):
        if p not in index:
            index[p] = points.InsertNextPoint(p)
        return index[p]

    def add(cell_type, ids):
        id_list = vtk.vtkIdList()
        for i in ids:
            id_list.InsertNextId(i)
        grid.InsertNextCell(cell_type, id_list)

    def add_polyhedron(faces):
        stream = [len(faces)]
        for face in faces:
            stream += [len(face)] + [point(p) for p in face]
        add(vtk.VTK_POLYHEDRON, stream)

    # The cube's faces hold the points where the x = 2 face is split: the four faces that meet
    # it are pentagons, as in OpenFOAM's meshes.
    coarse = [[(0, 0, 0), (0, 2, 0), (2, 2, 0), (2, 1, 0), (2, 0, 0)],
              [(0, 0, 2), (2, 0, 2), (2, 1, 2), (2, 2, 2), (0, 2, 2)],
              [(0, 0, 0), (2, 0, 0), (2, 0, 1), (2, 0, 2), (0, 0, 2)],
              [(0, 2, 0), (0, 2, 2), (2, 2, 2), (2, 2, 1), (2, 2, 0)],
              [(0, 0, 0), (0, 0, 2), (0, 2, 2), (0, 2, 0)]]
    for j in range(2):
        for k in range(2):
            coarse.append([(2, j, k), (2, j + 1, k), (2, j + 1, k + 1), (2, j, k + 1)])
    add_polyhedron(coarse)
    for i in range(2, 4):
        for j in range(2):
            for k in range(2):
                add(vtk.VTK_HEXAHEDRON, [point((i + a, j + b, k + c)) for c in range(2)
                                         for (a, b) in ((0, 0), (1, 0), (1, 1), (0, 1))])
    apex = (-1, 1, 1)
    side = [(0, 0, 0), (0, 0, 2), (0, 2, 2), (0, 2, 0)]
    add_polyhedron([list(reversed(side))] + [[side[n], side[(n + 1) % 4], apex] for n in range(4)])
    ring = [(5.5 + 0.5 * c, 1 + 0.5 * s) for c, s in ((1, 0), (0.5, 0.75 ** 0.5), (-0.5, 0.75 ** 0.5),
                                                      (-1, 0), (-0.5, -(0.75 ** 0.5)), (0.5, -(0.75 ** 0.5)))]
    bottom = [(x, y, 0.0) for x, y in ring]
    upper = [(x, y, 1.0) for x, y in ring]
    sides = [[bottom[n], bottom[(n + 1) % 6], upper[(n + 1) % 6], upper[n]] for n in range(6)]
    add_polyhedron([list(reversed(bottom)), upper] + sides)
    grid.SetPoints(points)
    add_test_arrays(grid, lambda x, y, z: x * y + z * z)
    return grid


def write_polyhedra():
    """The polyhedra mesh as vtk_polyhedra.vtu (appended raw, zlib; VTK 9.1 writes the face
    streams, "faces" and "faceoffsets") and ../vtk/vtk_polyhedra.vtk (legacy, file version 5.1,
    binary) and ../vtk/vtk_polyhedra_42.vtk (version 4.2, ascii)."""
    grid = polyhedra_mesh()
    write_xml(grid, "vtk_polyhedra.vtu")
    for name, version, binary in (("vtk_polyhedra", None, True), ("vtk_polyhedra_42", 42, False)):
        legacy = vtk.vtkUnstructuredGridWriter()
        legacy.SetInputData(grid)
        legacy.SetFileName(f"../vtk/{name}.vtk")
        if version:
            legacy.SetFileVersion(version)
        if binary:
            legacy.SetFileTypeToBinary()
        legacy.Write()


def quadratic_mesh(curved=True):
    """One cell of each quadratic type volstream reads, side by side along x, and a second
    quadratic hexahedron sharing a face with the first: every node at its parametric place in a
    unit cell (a unit cube, or the part of it a tet, wedge or pyramid fills), then, if `curved`,
    moved by a smooth map, so that the cells are curved. Returns the grid (point
    arrays f = 1 + 2x + 3y + 4z, linear, and g = xy + z^2 + x^2, a cell array cell_id) and
    probes: rows (x, y, z, g) where VTK's own cell puts each of its nodes and the parametric
    centres of its quad faces and body (the corners of volstream's split), with the value of g
    that the cell's shape functions give there."""
    grid = vtk.vtkUnstructuredGrid()
    points = vtk.vtkPoints()
    index = {}

    def curve(x, y, z):
        if not curved:
            return (x, y, z)
        return (x + 0.05 * y * y, y + 0.04 * z * z, z + 0.06 * y * (1 - y))

    def point(p):
        key = tuple(round(c, 9) for c in p)
        if key not in index:
            index[key] = points.InsertNextPoint(curve(*key))
        return index[key]

    cells = []
    for origin, cell_class in ((0, vtk.vtkQuadraticHexahedron), (1, vtk.vtkQuadraticHexahedron),
                               (3, vtk.vtkTriQuadraticHexahedron), (5, vtk.vtkQuadraticTetra),
                               (7, vtk.vtkQuadraticWedge), (9, vtk.vtkBiQuadraticQuadraticWedge),
                               (11, vtk.vtkQuadraticPyramid), (13, vtk.vtkBiQuadraticQuadraticHexahedron)):
        cell = cell_class()
        pcoords = cell.GetParametricCoords()
        ids = vtk.vtkIdList()
        for n in range(cell.GetNumberOfPoints()):
            r, s, t = pcoords[3 * n:3 * n + 3]
            if cell_class is vtk.vtkQuadraticPyramid:  # VTK's parametric apex is (0,0,1): put it above the centre
                r, s = r + 0.5 * t * (1 - 2 * r), s + 0.5 * t * (1 - 2 * s)
            ids.InsertNextId(point((origin + r, s, t)))
        grid.InsertNextCell(cell.GetCellType(), ids)
        cells.append(cell_class)
    grid.SetPoints(points)
    add_test_arrays(grid, lambda x, y, z: x * y + z * z + x * x)
    return grid, quadratic_probes(grid)


def quadratic_probes(grid):
    g = grid.GetPointData().GetArray("g")
    rows = []
    for c in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(c)
        n = cell.GetNumberOfPoints()
        own = cell.GetParametricCoords()
        at = [tuple(own[3 * k:3 * k + 3]) for k in range(n)]
        if cell.GetCellType() in (vtk.VTK_QUADRATIC_HEXAHEDRON, vtk.VTK_BIQUADRATIC_QUADRATIC_HEXAHEDRON):
            at += [(0, .5, .5), (1, .5, .5), (.5, 0, .5), (.5, 1, .5), (.5, .5, 0), (.5, .5, 1), (.5, .5, .5)]
        if cell.GetCellType() == vtk.VTK_QUADRATIC_WEDGE:
            at += [(.5, 0, .5), (.5, .5, .5), (0, .5, .5)]
        if cell.GetCellType() == vtk.VTK_QUADRATIC_PYRAMID:
            at += [(.5, .5, 0)]
        for pc in at:
            x, weights = [0.0] * 3, [0.0] * n
            cell.EvaluateLocation(vtk.reference(0), pc, x, weights)
            value = sum(weights[k] * g.GetValue(cell.GetPointId(k)) for k in range(n))
            rows.append((*x, value))
    return rows


def write_quadratic():
    """The curved quadratic cells as vtk_quadratic.vtu (appended raw) and ../vtk/vtk_quadratic.vtk
    (legacy 5.1, binary), and their probes as vtk_quadratic_probes.txt; the straight ones as
    vtk_quadratic_straight.vtu (ascii)."""
    grid, probes = quadratic_mesh()
    write_xml(grid, "vtk_quadratic.vtu")
    legacy = vtk.vtkUnstructuredGridWriter()
    legacy.SetInputData(grid)
    legacy.SetFileName("../vtk/vtk_quadratic.vtk")
    legacy.SetFileTypeToBinary()
    legacy.Write()
    write_xml(quadratic_mesh(curved=False)[0], "vtk_quadratic_straight.vtu", ascii=True)
    with open("vtk_quadratic_probes.txt", "w") as out:
        out.write("# x y z g: VTK's quadratic cells' nodes and face and body centres (make_vtk_files.py)\n")
        for row in probes:
            out.write(" ".join(repr(v) for v in row) + "\n")


def lagrange_mesh():
    """VTK's Lagrange tetra, hexahedron and wedge of order 1 and 2 as vtkCellTypeSource makes them
    (a unit cube of each: 12 tets, 1 hex, 2 wedges), side by side along x (origin 2 * k for the
    k-th), curved by the smooth map of quadratic_mesh(), with add_test_arrays' arrays
    (g = xy + z^2 + x^2). Returns it and its twin, the same points and cells typed as the linear
    and quadratic cells (10, 24, 12, 29, 13, 32), after checking that every Lagrange node lies where
    the twin's cell puts its node of the same index."""
    twins = {(vtk.VTK_LAGRANGE_TETRAHEDRON, 1): vtk.vtkTetra, (vtk.VTK_LAGRANGE_TETRAHEDRON, 2): vtk.vtkQuadraticTetra,
             (vtk.VTK_LAGRANGE_HEXAHEDRON, 1): vtk.vtkHexahedron,
             (vtk.VTK_LAGRANGE_HEXAHEDRON, 2): vtk.vtkTriQuadraticHexahedron,
             (vtk.VTK_LAGRANGE_WEDGE, 1): vtk.vtkWedge, (vtk.VTK_LAGRANGE_WEDGE, 2): vtk.vtkBiQuadraticQuadraticWedge}
    grids = [vtk.vtkUnstructuredGrid(), vtk.vtkUnstructuredGrid()]
    points = vtk.vtkPoints()
    for k, ((cell_type, order), twin_class) in enumerate(twins.items()):
        block = cell_type_source(cell_type, order)
        first = points.GetNumberOfPoints()
        for i in range(block.GetNumberOfPoints()):
            x, y, z = block.GetPoint(i)
            x += 2 * k
            points.InsertNextPoint(x + 0.05 * y * y, y + 0.04 * z * z, z + 0.06 * y * (1 - y))
        for c in range(block.GetNumberOfCells()):
            cell = block.GetCell(c)
            twin = twin_class()
            own = twin.GetParametricCoords()
            nodes = [block.GetPoint(cell.GetPointId(i)) for i in range(cell.GetNumberOfPoints())]
            linear = {vtk.VTK_LAGRANGE_TETRAHEDRON: vtk.vtkTetra, vtk.VTK_LAGRANGE_HEXAHEDRON: vtk.vtkHexahedron,
                      vtk.VTK_LAGRANGE_WEDGE: vtk.vtkWedge}[cell_type]()
            for i in range(linear.GetNumberOfPoints()):
                linear.GetPoints().SetPoint(i, nodes[i])
            for i in range(twin.GetNumberOfPoints()):
                x, weights = [0.0] * 3, [0.0] * linear.GetNumberOfPoints()
                linear.EvaluateLocation(vtk.reference(0), own[3 * i:3 * i + 3], x, weights)
                assert max(abs(a - b) for a, b in zip(x, nodes[i])) < 1e-9, (cell_type, order, i)
            ids = vtk.vtkIdList()
            for i in range(cell.GetNumberOfPoints()):
                ids.InsertNextId(first + cell.GetPointId(i))
            grids[0].InsertNextCell(cell_type, ids)
            grids[1].InsertNextCell(twin.GetCellType(), ids)
    for grid in grids:
        grid.SetPoints(points)
        add_test_arrays(grid, lambda x, y, z: x * y + z * z + x * x)
    return grids


def lagrange_hexahedra():
    """Lagrange hexahedra of order 3, 4, 5 and 6 as vtkCellTypeSource makes them (a unit cube each,
    at x = 0, 2, 4, 6), curved as lagrange_mesh()'s, with add_test_arrays' arrays; and their twin:
    the same points, each cell as the p^3 linear hexes of its node lattice (found from where
    vtkCellTypeSource puts each node), in the order volstream splits them (x fastest, then y, z)."""
    grid, twin = vtk.vtkUnstructuredGrid(), vtk.vtkUnstructuredGrid()
    points = vtk.vtkPoints()
    corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    for k, order in enumerate((3, 4, 5, 6)):
        block = cell_type_source(vtk.VTK_LAGRANGE_HEXAHEDRON, order)
        first = points.GetNumberOfPoints()
        for i in range(block.GetNumberOfPoints()):
            x, y, z = block.GetPoint(i)
            x += 2 * k
            points.InsertNextPoint(x + 0.05 * y * y, y + 0.04 * z * z, z + 0.06 * y * (1 - y))
        cell = block.GetCell(0)
        ids = [first + cell.GetPointId(n) for n in range(cell.GetNumberOfPoints())]
        grid.InsertNextCell(vtk.VTK_LAGRANGE_HEXAHEDRON, len(ids), ids)
        at = {tuple(round(c * order) for c in block.GetPoint(cell.GetPointId(n))): ids[n]
              for n in range(cell.GetNumberOfPoints())}
        for c in range(order):
            for b in range(order):
                for a in range(order):
                    twin.InsertNextCell(vtk.VTK_HEXAHEDRON, 8, [at[(a + u, b + v, c + w)] for u, v, w in corners])
    for g in (grid, twin):
        g.SetPoints(points)
        add_test_arrays(g, lambda x, y, z: x * y + z * z + x * x)
    return grid, twin


def lagrange_tetra():
    """Lagrange tetra of order 3, 4, 5 and 6 as vtkCellTypeSource makes them (12 straight tets
    filling a unit cube, at x = 0, 2, 4, 6), with add_test_arrays' arrays."""
    grid = vtk.vtkUnstructuredGrid()
    points = vtk.vtkPoints()
    for k, order in enumerate((3, 4, 5, 6)):
        block = cell_type_source(vtk.VTK_LAGRANGE_TETRAHEDRON, order)
        first = points.GetNumberOfPoints()
        for i in range(block.GetNumberOfPoints()):
            x, y, z = block.GetPoint(i)
            points.InsertNextPoint(x + 2 * k, y, z)
        for c in range(block.GetNumberOfCells()):
            cell = block.GetCell(c)
            grid.InsertNextCell(vtk.VTK_LAGRANGE_TETRAHEDRON, cell.GetNumberOfPoints(),
                                [first + cell.GetPointId(n) for n in range(cell.GetNumberOfPoints())])
    grid.SetPoints(points)
    add_test_arrays(grid, lambda x, y, z: x * y + z * z + x * x)
    return grid


def pre_vtk91_numbering(grid):
    """A copy of `grid` whose Lagrange hexahedra list their nodes as before VTK 9.1 (the nodes
    inside edges (2,6) and (3,7), edges 10 and 11, the other way round: 18 and 19 at order 2)."""
    old = vtk.vtkUnstructuredGrid()
    old.DeepCopy(grid)
    for c in range(old.GetNumberOfCells()):
        n = old.GetCell(c).GetNumberOfPoints()
        if old.GetCellType(c) == vtk.VTK_LAGRANGE_HEXAHEDRON and n >= 27:
            ids = vtk.vtkIdList()
            old.GetCellPoints(c, ids)
            nodes = [ids.GetId(i) for i in range(n)]
            m = round(n ** (1 / 3)) - 2  # nodes inside an edge
            e10, e11 = 8 + 10 * m, 8 + 11 * m
            nodes[e10:e10 + m], nodes[e11:e11 + m] = nodes[e11:e11 + m], nodes[e10:e10 + m]
            old.ReplaceCell(c, n, nodes)
    return old


def same_cells(a, b):
    return a.GetNumberOfCells() == b.GetNumberOfCells() and all(
        a.GetCellType(c) == b.GetCellType(c) and
        [a.GetCell(c).GetPointId(i) for i in range(a.GetCell(c).GetNumberOfPoints())] ==
        [b.GetCell(c).GetPointId(i) for i in range(b.GetCell(c).GetNumberOfPoints())] for c in range(a.GetNumberOfCells()))


def write_lagrange():
    """The Lagrange cells as vtk_lagrange.vtu and their twin as vtk_lagrange_twin.vtu (ascii);
    the Lagrange cells as files older than VTK 9.1 have them (the order-2 hexahedron's nodes 18 and
    19 swapped): vtk_lagrange_pre91.vtu (XML version 1.0) and ../vtk/vtk_lagrange_42.vtk (legacy
    4.2), each checked to read back in VTK as the current numbering; and ../vtk/vtk_lagrange.vtk
    (legacy 5.1, current numbering)."""
    grid, twin = lagrange_mesh()
    for data, name in ((grid, "vtk_lagrange.vtu"), (twin, "vtk_lagrange_twin.vtu"),
                       (pre_vtk91_numbering(grid), "vtk_lagrange_pre91.vtu")):
        write_xml(data, name, ascii=True)
    for data, name, version in ((grid, "../vtk/vtk_lagrange.vtk", 51),
                                (pre_vtk91_numbering(grid), "../vtk/vtk_lagrange_42.vtk", 42)):
        legacy = vtk.vtkUnstructuredGridWriter()
        legacy.SetInputData(data)
        legacy.SetFileName(name)
        legacy.SetFileVersion(version)
        legacy.Write()
    hexahedra, hexahedra_twin = lagrange_hexahedra()
    for data, name in ((hexahedra, "vtk_lagrange_hex.vtu"), (hexahedra_twin, "vtk_lagrange_hex_twin.vtu"),
                       (pre_vtk91_numbering(hexahedra), "vtk_lagrange_hex_pre91.vtu"),
                       (lagrange_tetra(), "vtk_lagrange_tet.vtu")):
        write_xml(data, name)
    for name in ("vtk_lagrange_pre91.vtu", "vtk_lagrange_hex_pre91.vtu"):  # as files older than VTK 9.1
        with open(name, "rb") as f:
            data = f.read()
        with open(name, "wb") as f:
            f.write(data.replace(b'version="2.2"', b'version="1.0"', 1))
    for name, reader, current in (("vtk_lagrange_pre91.vtu", vtk.vtkXMLUnstructuredGridReader(), grid),
                                  ("../vtk/vtk_lagrange_42.vtk", vtk.vtkUnstructuredGridReader(), grid),
                                  ("../vtk/vtk_lagrange.vtk", vtk.vtkUnstructuredGridReader(), grid),
                                  ("vtk_lagrange_hex_pre91.vtu", vtk.vtkXMLUnstructuredGridReader(), hexahedra)):
        reader.SetFileName(name)
        reader.Update()
        assert same_cells(reader.GetOutput(), current), name + ": VTK does not read it as the current numbering"


if __name__ == "__main__":
    mesh = tets()
    write_compressed(mesh)
    write_pieces(mesh)
    write_blocks()
    write_voxels()
    write_polyhedra()
    write_quadratic()
    write_lagrange()
