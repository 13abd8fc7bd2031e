// VTK XML unstructured grids (.vtu) and ParaView collections (.pvd), read and written.
//
// Reading supports every encoding VTK writes: DataArray format "ascii", "binary" (inline base64)
// and "appended" (<AppendedData encoding="raw"> or "base64"; offsets count from the byte after
// the "_" marker, in characters for base64), with or without compressor="vtkZLibDataCompressor"
// (blocked zlib), header_type UInt32 (the default, also of version 0.1 files) or UInt64, byte
// order LittleEndian or BigEndian (swapped), Float32/Float64 points, any integer type for
// connectivity, offsets and types, and numeric point and cell arrays of any type and component
// count (converted to double). Arrays of other types (String, Bit) are skipped.
//
// Several <Piece>s are concatenated in file order (indices offset by the points before them);
// every piece must carry the same point and cell arrays.
//
// Every malformed input is an InputError naming the file: declared sizes are checked against the
// file (and zlib's maximum ratio) before anything is allocated. read_vtu ends with check_mesh.
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include "volstream/umesh/mesh_data.h"

namespace vs {

MeshData read_vtu(const std::filesystem::path& file);

struct VtuWriteOptions {
  // ascii: values as text (zlib and the header type do not apply); base64: inline base64
  // ("binary" in VTK's words); appended_*: one <AppendedData> section, base64 or raw bytes.
  enum class Format { ascii, base64, appended_base64, appended_raw } format = Format::appended_raw;
  bool zlib = false;                 // compressor="vtkZLibDataCompressor"
  bool header_uint64 = true;         // header_type UInt64 (else UInt32)
  bool points_float64 = false;       // Points as Float64 (else Float32)
  bool indices_int64 = true;         // connectivity and offsets as Int64 (else Int32)
  uint64_t zlib_block_size = 32768;  // uncompressed bytes per zlib block
};

// Writes the mesh in the host's byte order (VTK reads either), point and cell arrays as Float32.
// The mesh is not validated, so that tests can write inconsistent meshes on purpose; values that
// do not fit the chosen index type (or a cell type over 255) are std::invalid_argument.
void write_vtu(const std::filesystem::path& file, const MeshData& mesh, const VtuWriteOptions& options = {});

// A time step of a .pvd collection: its time and its file (relative paths in the .pvd are taken
// relative to the .pvd's directory).
struct PvdStep {
  double time;
  std::filesystem::path file;
};

// The <DataSet timestep= file=> entries of a .pvd, sorted by time. InputError for a missing or bad
// attribute, two entries with the same time, no entries, or a part other than 0 (multi-part
// collections are not supported); the group attribute is ignored.
std::vector<PvdStep> read_pvd(const std::filesystem::path& file);
// Writes the steps in the given order, file paths relative to the .pvd's directory when possible.
void write_pvd(const std::filesystem::path& file, const std::vector<PvdStep>& steps);

}  // namespace vs
