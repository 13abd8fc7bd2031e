"""The mesh of FILE.vtu written again by VTK's own writer (appended raw, VTK's default block size
and level) uncompressed and with each compressor: t_none.vtu, t_zlib.vtu, t_lz4.vtu, t_lzma.vtu.
Debian's python3-vtk9: /usr/bin/python3 write_vtk_compressed.py FILE.vtu"""
import sys

import vtk

reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(sys.argv[1])
reader.Update()
for name in ("None", "ZLib", "LZ4", "LZMA"):
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetInputData(reader.GetOutput())
    writer.SetFileName(f"t_{name.lower()}.vtu")
    getattr(writer, f"SetCompressorTypeTo{name}")()
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.Write()
