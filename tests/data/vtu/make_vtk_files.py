"""Writes the vtk_* files of this directory (.vtu, .pvtu, .vtm and vtk_blocks/; and
../vtk/vtk_voxels.vtk) with VTK's own writers, so that
the reader is tested against files it did not write itself (tests/io/vtu_test.cpp).

Run from this directory with Debian's python3-vtk9: /usr/bin/python3 make_vtk_files.py
(the committed files come from VTK 9.1.0). The mesh: VTK's analytic "wavelet" on a 4x4x4 point
grid, split into 135 tets by vtkDataSetTriangleFilter, with its point scalar RTData.
"""
import vtk


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


if __name__ == "__main__":
    mesh = tets()
    write_compressed(mesh)
    write_pieces(mesh)
    write_blocks()
    write_voxels()
