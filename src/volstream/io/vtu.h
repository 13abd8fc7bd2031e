// VTK XML unstructured grids (.vtu), parallel ones (.pvtu), multiblocks of them (.vtm, read only),
// ParaView collections (.pvd) and file series (.series, read only), read and written.
//
// Reading supports every encoding VTK writes: DataArray format "ascii", "binary" (inline base64)
// and "appended" (<AppendedData encoding="raw"> or "base64"; offsets count from the byte after
// the "_" marker, in characters for base64), uncompressed or in compressed blocks of any of VTK's
// three compressors (vtkZLibDataCompressor; vtkLZ4DataCompressor: LZ4 blocks;
// vtkLZMADataCompressor: each block an .xz stream), header_type UInt32 (the default, also of
// version 0.1 files) or UInt64, byte order LittleEndian or BigEndian (swapped), Float32/Float64 points, any integer
// type for connectivity, offsets and types, and numeric point and cell arrays of any type and component count
// (converted to double). Arrays of other types (String, Bit) are skipped.
//
// Several <Piece>s are one mesh, joined by join_pieces (umesh/mesh_pieces.h): concatenated in
// file order, ghost cells dropped, the points they share welded; every piece must carry the same
// point and cell arrays.
//
// A .pvtu (VTK's parallel unstructured grid: a header naming one .vtu per piece) is read as the
// pieces of its files, joined the same way; so are the volume blocks of a .vtm.
//
// Every malformed input is an InputError naming the file: declared sizes are checked against the
// file (and the compressor's maximum ratio) before anything is allocated. read_vtu and read_pvtu
// end with check_mesh, as does read_vtm.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "volstream/umesh/cell_rebuild.h"
#include "volstream/umesh/mesh_data.h"

namespace vs {

// The splits of polyhedra and quadratic cells (umesh/cell_rebuild.h) a series' reads remember,
// so that a step on the mesh of the one before is split as it was, only its data combined (a
// foamToVTK series of polyhedra): used where a step is one .vtu of one piece, directly or as the
// one volume block of a .vtm; other steps are split anew.
struct SeriesSplits {
  SplitMemo polyhedra, quadratic;
};

MeshData read_vtu(const std::filesystem::path& file, SeriesSplits* splits = nullptr);
MeshData read_pvtu(const std::filesystem::path& file);
// A .vtm (VTK multiblock, as OpenFOAM's foamToVTK and SU2's multizone output write it): its .vtu
// and .pvtu blocks, at any depth, joined into one mesh; surface blocks (.vtp, .pvtp: boundary
// patches) are skipped; a block of another type, or none that is a volume, is an InputError.
// `blocks` (--region) reads only the data sets under the blocks it names: by a <Block>'s or
// <DataSet>'s name ("fluid", "internal": every one of that name) or by a path of names from the
// top ("fluid/internal"); a name that matches none is an InputError listing the file's blocks.
MeshData read_vtm(const std::filesystem::path& file, SeriesSplits* splits = nullptr,
                  const std::vector<std::string>& blocks = {});

// VTK's block compressors (the VTKFile's compressor attribute).
enum class VtuCompressor { none, zlib, lz4, lzma };

struct VtuWriteOptions {
  // ascii: values as text (compression and the header type do not apply); base64: inline base64
  // ("binary" in VTK's words); appended_*: one <AppendedData> section, base64 or raw bytes.
  enum class Format { ascii, base64, appended_base64, appended_raw } format = Format::appended_raw;
  VtuCompressor compressor = VtuCompressor::none;
  bool header_uint64 = true;    // header_type UInt64 (else UInt32)
  bool points_float64 = false;  // Points as Float64 (else Float32)
  bool indices_int64 = true;    // connectivity and offsets as Int64 (else Int32)
  uint64_t block_size = 32768;  // uncompressed bytes per compressed block
};

// Writes the mesh in the host's byte order (VTK reads either), point and cell arrays as Float32.
// The mesh is not validated, so that tests can write inconsistent meshes on purpose; values that
// do not fit the chosen index type (or a cell type over 255) are std::invalid_argument.
void write_vtu(const std::filesystem::path& file, const MeshData& mesh, const VtuWriteOptions& options = {});
// A .pvtu and one .vtu per piece beside it (FILE_STEM_0.vtu, ...), as write_vtu writes them; the
// pieces' arrays are declared as the first piece's.
void write_pvtu(const std::filesystem::path& file, const std::vector<MeshData>& pieces,
                const VtuWriteOptions& options = {});

// A time step of a .pvd collection: its time and its files, one per part (parallel writers, such
// as ParaView's, write a step's pieces as entries of one timestep with parts 0, 1, ...; a reader
// joins them with join_pieces). Relative paths in the .pvd are taken relative to its directory.
struct PvdStep {
  double time;
  std::vector<std::filesystem::path> parts;
};

// The <DataSet timestep= part= file=> entries of a .pvd grouped into steps, sorted by time, each
// step's parts by part number. InputError for a missing or bad attribute, two entries with the
// same time and part, or no entries; the group attribute is ignored.
std::vector<PvdStep> read_pvd(const std::filesystem::path& file);
// ParaView's file series (NAME.vtu.series, NAME.vtm.series; JSON, as OpenFOAM's foamToVTK writes a
// case's times): {"file-series-version": "1.0", "files": [{"name": FILE, "time": T}, ...]}, as
// steps of one part each, sorted by time; names relative to the series' directory. InputError for
// bad JSON, another version, an entry without a name or a finite time, two entries with the same
// time, or none.
std::vector<PvdStep> read_file_series(const std::filesystem::path& file);
// Writes the steps in the given order (parts numbered from 0), file paths relative to the .pvd's directory when
// possible.
void write_pvd(const std::filesystem::path& file, const std::vector<PvdStep>& steps);

}  // namespace vs
