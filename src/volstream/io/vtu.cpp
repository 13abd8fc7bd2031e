#include "volstream/io/vtu.h"

#include "volstream/core/xml.h"

#include <lz4.h>
#include <lzma.h>
#include <zlib.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <type_traits>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/io/atomic_file.h"
#include "volstream/io/base64.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/xml_scan.h"
#include "volstream/umesh/mesh_pieces.h"
#include "volstream/umesh/polyhedra.h"
#include "volstream/umesh/quadratic.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

// Limits on untrusted input, far above real meshes.
constexpr uint64_t kMaxFileBytes = uint64_t(1) << 40;
constexpr uint64_t kMaxValues = uint64_t(1) << 40;  // per array
constexpr uint64_t kMaxComponents = 1 << 16;
// An LZMA block's decoder may allocate its dictionary: VTK's highest level (9) needs 65 MiB.
constexpr uint64_t kLzmaMemoryLimit = uint64_t(256) << 20;

// VTK's block compressors: the name in the file, the short name for errors, and how far a block
// can expand (a declared size beyond max_ratio x compressed + slack is a lie, refused before
// the output is allocated).
struct CompressorInfo {
  VtuCompressor type;
  std::string_view name, short_name;
  uint64_t max_ratio, slack;
};
constexpr CompressorInfo kCompressors[] = {
    {VtuCompressor::zlib, "vtkZLibDataCompressor", "zlib", 1032, 64},  // deflate's own limit
    {VtuCompressor::lz4, "vtkLZ4DataCompressor", "LZ4", 256, 64},      // a byte of a match's length per 255
    // The .xz format's limit is near 7000:1 (6800:1 measured for 100 MB of zeros at level 9).
    {VtuCompressor::lzma, "vtkLZMADataCompressor", "LZMA", 8192, 1024},
};
const CompressorInfo& compressor_info(VtuCompressor type) { return kCompressors[int(type) - 1]; }

std::string str(uint64_t v) { return std::to_string(v); }

// ---------------------------------------------------------------------------------------------
// The numeric types of VTK's XML DataArrays.

enum class Scalar { i8, u8, i16, u16, i32, u32, i64, u64, f32, f64 };
struct ScalarInfo {
  std::string_view name;
  Scalar type;
  size_t bytes;
  bool is_float;
};
constexpr ScalarInfo kScalars[] = {{"Int8", Scalar::i8, 1, false},    {"UInt8", Scalar::u8, 1, false},
                                   {"Int16", Scalar::i16, 2, false},  {"UInt16", Scalar::u16, 2, false},
                                   {"Int32", Scalar::i32, 4, false},  {"UInt32", Scalar::u32, 4, false},
                                   {"Int64", Scalar::i64, 8, false},  {"UInt64", Scalar::u64, 8, false},
                                   {"Float32", Scalar::f32, 4, true}, {"Float64", Scalar::f64, 8, true}};

std::optional<ScalarInfo> scalar_info(std::string_view name) {
  for (const ScalarInfo& s : kScalars)
    if (s.name == name) return s;
  return std::nullopt;
}
const ScalarInfo& scalar_info(Scalar type) { return kScalars[int(type)]; }

// Calls f with a value of the C++ type stored for `type` (to pick the type, not the value).
template <typename F>
decltype(auto) with_scalar_type(Scalar type, F&& f) {
  switch (type) {
    case Scalar::i8:
      return f(int8_t{});
    case Scalar::u8:
      return f(uint8_t{});
    case Scalar::i16:
      return f(int16_t{});
    case Scalar::u16:
      return f(uint16_t{});
    case Scalar::i32:
      return f(int32_t{});
    case Scalar::u32:
      return f(uint32_t{});
    case Scalar::i64:
      return f(int64_t{});
    case Scalar::u64:
      return f(uint64_t{});
    case Scalar::f32:
      return f(float{});
    case Scalar::f64:
      break;
  }
  return f(double{});
}

template <typename T>
T load(const char* p, bool swap) {
  char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// =============================================================================================
// Reading

struct VtuFile {
  std::string name;  // for errors
  std::string text;  // the whole file
  XmlDocument doc;
  bool swap_bytes = false;  // the file's byte order is not the host's
  size_t header_bytes = 4;  // UInt32 or UInt64 binary headers
  VtuCompressor compressor = VtuCompressor::none;
  bool appended_base64 = false;
  size_t appended_end = 0;          // end of the appended section (base64: the next '<')
  bool pre_vtk91_lagrange = false;  // version below 2.2: Lagrange hexahedra in the old node order
};

// Appended raw bytes, read in order from an offset; the same interface as Base64Reader.
class RawReader {
 public:
  RawReader(std::string_view bytes, const std::string& file, std::string what)
      : bytes_(bytes), file_(file), what_(std::move(what)) {}
  void read(void* dst, size_t n) {
    if (n > bytes_.size() - pos_) input_error(file_, what_ + ": truncated file (the appended data end too early)");
    std::memcpy(dst, bytes_.data() + pos_, n);
    pos_ += n;
  }
  uint64_t max_remaining() const { return bytes_.size() - pos_; }

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
  const std::string& file_;
  std::string what_;
};

template <typename Source>
uint64_t read_header_word(const VtuFile& f, Source& src) {
  char b[8];
  src.read(b, f.header_bytes);
  return f.header_bytes == 8 ? load<uint64_t>(b, f.swap_bytes) : load<uint32_t>(b, f.swap_bytes);
}

[[noreturn]] void size_mismatch(const VtuFile& f, const std::string& what, uint64_t bytes, uint64_t expected) {
  input_error(f.name, what + ": the data hold " + str(bytes) + " bytes, expected " + str(expected));
}

// Uncompressed binary data: [byte count] [bytes].
template <typename Source>
std::string read_plain_blob(const VtuFile& f, Source& src, const std::string& what, uint64_t expected) {
  const uint64_t bytes = read_header_word(f, src);
  if (bytes != expected) size_mismatch(f, what, bytes, expected);
  if (bytes > src.max_remaining()) input_error(f.name, what + ": truncated file (" + str(bytes) + " bytes declared)");
  std::string out(bytes, '\0');
  src.read(out.data(), bytes);
  return out;
}

// One compressed block into out[0..want): false when its data are corrupt or do not give exactly
// `want` bytes (`why` then says what the decoder found).
bool decode_block(VtuCompressor type, std::string_view packed, char* out, uint64_t want, std::string& why) {
  switch (type) {
    case VtuCompressor::zlib: {
      uLongf got = uLongf(want);
      const int rc = uncompress(reinterpret_cast<Bytef*>(out), &got, reinterpret_cast<const Bytef*>(packed.data()),
                                uLong(packed.size()));
      why = zError(rc);
      return rc == Z_OK && got == want;
    }
    case VtuCompressor::lz4: {
      why = "not a valid LZ4 block of that size";
      if (packed.size() > LZ4_MAX_INPUT_SIZE || want > uint64_t(INT32_MAX)) return false;
      return LZ4_decompress_safe(packed.data(), out, int(packed.size()), int(want)) == int64_t(want);
    }
    case VtuCompressor::lzma: {
      uint64_t memory = kLzmaMemoryLimit;
      size_t in = 0, got = 0;
      const lzma_ret rc =
          lzma_stream_buffer_decode(&memory, 0, nullptr, reinterpret_cast<const uint8_t*>(packed.data()), &in,
                                    packed.size(), reinterpret_cast<uint8_t*>(out), &got, want);
      why = rc == LZMA_MEMLIMIT_ERROR ? "needs more than 256 MiB to decode"
            : rc == LZMA_OK           ? "size differs from the header's"
                                      : "not a valid .xz stream (lzma error " + std::to_string(int(rc)) + ")";
      return rc == LZMA_OK && got == want && in == packed.size();
    }
    case VtuCompressor::none:
      break;
  }
  return false;
}

// Compressed binary data: [#blocks] [block size] [last block size or 0] [compressed size of each
// block] [the compressed blocks].
template <typename Source>
std::string read_compressed_blob(const VtuFile& f, Source& src, const std::string& what, uint64_t expected) {
  const CompressorInfo& codec = compressor_info(f.compressor);
  const uint64_t blocks = read_header_word(f, src);
  const uint64_t block_size = read_header_word(f, src);
  const uint64_t last_size = read_header_word(f, src);
  if (blocks > src.max_remaining() / f.header_bytes)
    input_error(f.name, what + ": truncated file (" + str(blocks) + " compressed blocks declared)");
  if (last_size > block_size) input_error(f.name, what + ": bad compression header (last block over block size)");
  const uint64_t last_bytes = last_size ? last_size : block_size;
  const bool too_big = blocks > 1 && block_size > 0 && blocks - 1 > (kMaxValues * 8) / block_size;
  const uint64_t total = blocks == 0 ? 0 : too_big ? UINT64_MAX : (blocks - 1) * block_size + last_bytes;
  if (total != expected) size_mismatch(f, what, total, expected);

  std::vector<uint64_t> compressed(blocks);
  uint64_t compressed_total = 0;
  for (uint64_t b = 0; b < blocks; ++b) {
    compressed[b] = read_header_word(f, src);
    const uint64_t block_bytes = b + 1 == blocks ? last_bytes : block_size;
    const uint64_t room = src.max_remaining();
    if (compressed[b] > room || compressed_total > room - compressed[b])
      input_error(f.name, what + ": truncated file (compressed block " + str(b) + " is cut off)");
    if (block_bytes > compressed[b] * codec.max_ratio + codec.slack)
      input_error(f.name, what + ": compressed block " + str(b) + " of " + str(compressed[b]) +
                              " bytes cannot hold the " + str(block_bytes) + " bytes declared");
    compressed_total += compressed[b];
  }

  // The compressed blocks are read in order (a base64 source decodes as it goes), then inflated
  // in parallel: each block is a stream of its own into its own part of the output (inflating
  // LZMA's blocks costs about 10 ns a byte on one core, bench/RESULTS.md).
  std::string packed(compressed_total, '\0');
  src.read(packed.data(), packed.size());
  std::vector<uint64_t> packed_at(blocks + 1, 0);
  for (uint64_t b = 0; b < blocks; ++b) packed_at[b + 1] = packed_at[b] + compressed[b];
  std::string out(total, '\0');
  auto decode = [&](int64_t b, std::string& why) {
    const uint64_t want = uint64_t(b) + 1 == blocks ? last_bytes : block_size;
    return decode_block(f.compressor, std::string_view(packed).substr(packed_at[b], compressed[b]),
                        out.data() + uint64_t(b) * block_size, want, why);
  };
  const int64_t bad = first_failing(
      int64_t(blocks),
      [&](int64_t b) {
        std::string why;
        return decode(b, why);
      },
      1);
  if (bad >= 0) {
    std::string why;
    decode(bad, why);
    input_error(f.name, what + ": corrupt " + std::string(codec.short_name) + " data in block " + str(uint64_t(bad)) +
                            " (" + why + ")");
  }
  return out;
}

template <typename Source>
std::string read_blob(const VtuFile& f, Source& src, const std::string& what, uint64_t expected) {
  if (f.compressor == VtuCompressor::none) return read_plain_blob(f, src, what, expected);
  return read_compressed_blob(f, src, what, expected);
}

// Values as the reader wants them: double for coordinates and data, uint64_t for indices (which
// must then be integers and not negative), int64_t for offsets where -1 means none (integers).
template <typename Out, typename Stored>
Out convert_value(const VtuFile& f, Stored v, const std::string& what) {
  if constexpr (std::is_same_v<Out, double>) {
    return double(v);
  } else if constexpr (std::is_same_v<Out, int64_t>) {
    if constexpr (std::is_same_v<Stored, uint64_t>)
      if (v > uint64_t(INT64_MAX)) input_error(f.name, what + ": value " + std::to_string(v) + " is out of range");
    return int64_t(v);
  } else {
    if constexpr (std::is_signed_v<Stored>)
      if (v < 0) input_error(f.name, what + ": negative value " + std::to_string(int64_t(v)));
    return uint64_t(v);
  }
}

template <typename Out>
std::vector<Out> convert_binary(const VtuFile& f, const std::string& bytes, Scalar type, const std::string& what) {
  return with_scalar_type(type, [&](auto tag) {
    using Stored = decltype(tag);
    std::vector<Out> out(bytes.size() / sizeof(Stored));
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = convert_value<Out>(f, load<Stored>(bytes.data() + i * sizeof(Stored), f.swap_bytes), what);
    return out;
  });
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

// One ASCII value, parsed as the declared type (a Float32 value as float, as in binary files).
template <typename Stored>
Stored parse_token(const VtuFile& f, std::string_view token, const std::string& what) {
  using Parsed = std::conditional_t<std::is_floating_point_v<Stored>, Stored,
                                    std::conditional_t<std::is_signed_v<Stored>, int64_t, uint64_t>>;
  Parsed v{};
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size())
    input_error(f.name, what + ": bad value '" + std::string(token.substr(0, 32)) + "'");
  if constexpr (std::is_floating_point_v<Stored>) {
    return v;
  } else {
    if (v < Parsed(std::numeric_limits<Stored>::min()) || v > Parsed(std::numeric_limits<Stored>::max()))
      input_error(f.name, what + ": value " + std::string(token.substr(0, 32)) + " is out of range for its type");
    return Stored(v);
  }
}

template <typename Out>
std::vector<Out> parse_ascii(const VtuFile& f, std::string_view text, Scalar type, uint64_t count,
                             const std::string& what) {
  return with_scalar_type(type, [&](auto tag) {
    using Stored = decltype(tag);
    std::vector<Out> out;
    out.reserve(std::min<uint64_t>(count, text.size() / 2 + 1));  // a value takes two characters at least
    for (size_t pos = 0;;) {
      while (pos < text.size() && is_space(text[pos])) ++pos;
      if (pos == text.size()) break;
      size_t end = pos;
      while (end < text.size() && !is_space(text[end])) ++end;
      if (out.size() == count) input_error(f.name, what + ": more than the " + str(count) + " values expected");
      out.push_back(convert_value<Out>(f, parse_token<Stored>(f, text.substr(pos, end - pos), what), what));
      pos = end;
    }
    if (out.size() != count) input_error(f.name, what + ": " + str(out.size()) + " values, expected " + str(count));
    return out;
  });
}

const std::string& required_attribute(const VtuFile& f, const XmlElement& e, std::string_view key,
                                      const std::string& what) {
  const std::string* v = e.attribute(key);
  if (!v) input_error(f.name, what + ": <" + e.name + "> has no " + std::string(key) + " attribute");
  return *v;
}

uint64_t parse_uint(const VtuFile& f, const std::string& text, const std::string& what) {
  uint64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty())
    input_error(f.name, what + ": '" + text.substr(0, 32) + "' is not a non-negative integer");
  return v;
}

uint64_t uint_attribute(const VtuFile& f, const XmlElement& e, std::string_view key, const std::string& what) {
  return parse_uint(f, required_attribute(f, e, key, what), what + " " + std::string(key));
}

uint64_t components_of(const VtuFile& f, const XmlElement& array, const std::string& what) {
  const std::string* text = array.attribute("NumberOfComponents");
  const uint64_t n = text ? parse_uint(f, *text, what + " NumberOfComponents") : 1;
  if (n < 1 || n > kMaxComponents) input_error(f.name, what + ": NumberOfComponents " + str(n) + " is out of range");
  return n;
}

std::string_view element_text(const VtuFile& f, const XmlElement& e) {
  return std::string_view(f.text).substr(e.text_begin, e.text_end - e.text_begin);
}

template <typename Out, typename Source>
std::vector<Out> read_binary_values(const VtuFile& f, Source&& src, const ScalarInfo& type, uint64_t count,
                                    const std::string& what) {
  return convert_binary<Out>(f, read_blob(f, src, what, count * type.bytes), type.type, what);
}

template <typename Out>
std::vector<Out> read_appended_values(const VtuFile& f, const XmlElement& array, const ScalarInfo& type, uint64_t count,
                                      const std::string& what) {
  if (!f.doc.has_appended) input_error(f.name, what + ": format=\"appended\" but the file has no <AppendedData>");
  const uint64_t offset = uint_attribute(f, array, "offset", what);
  const uint64_t section = f.appended_end - f.doc.appended_begin;
  if (offset > section)
    input_error(f.name, what + ": offset " + str(offset) + " is past the end of the appended data (truncated file?)");
  const std::string_view data = std::string_view(f.text).substr(f.doc.appended_begin + offset, section - offset);
  if (f.appended_base64) return read_binary_values<Out>(f, Base64Reader(data, f.name, what), type, count, what);
  return read_binary_values<Out>(f, RawReader(data, f.name, what), type, count, what);
}

// A DataArray's `count` values, whatever its encoding.
template <typename Out>
std::vector<Out> read_values(const VtuFile& f, const XmlElement& array, const ScalarInfo& type, uint64_t count,
                             const std::string& what) {
  if constexpr (!std::is_same_v<Out, double>)
    if (type.is_float) input_error(f.name, what + ": must be of an integer type, not " + std::string(type.name));
  if (count > kMaxValues) input_error(f.name, what + ": " + str(count) + " values is absurdly many");
  const std::string& format = required_attribute(f, array, "format", what);
  if (format == "ascii") return parse_ascii<Out>(f, element_text(f, array), type.type, count, what);
  if (format == "binary")
    return read_binary_values<Out>(f, Base64Reader(element_text(f, array), f.name, what), type, count, what);
  if (format == "appended") return read_appended_values<Out>(f, array, type, count, what);
  input_error(f.name, what + ": unknown format \"" + format + "\"");
}

ScalarInfo numeric_type(const VtuFile& f, const XmlElement& array, const std::string& what) {
  const std::string& name = required_attribute(f, array, "type", what);
  const std::optional<ScalarInfo> type = scalar_info(name);
  if (!type) input_error(f.name, what + ": unsupported data type " + name);
  return *type;
}

const XmlElement& required_child(const VtuFile& f, const XmlElement& parent, std::string_view name,
                                 const std::string& what) {
  const XmlElement* e = parent.child(name);
  if (!e) input_error(f.name, what + ": <" + parent.name + "> has no <" + std::string(name) + ">");
  return *e;
}

const XmlElement* find_named_array(const XmlElement& parent, std::string_view name) {
  for (const XmlElement& e : parent.children) {
    const std::string* n = e.attribute("Name");
    if (e.name == "DataArray" && n && *n == name) return &e;
  }
  return nullptr;
}

const XmlElement& named_array(const VtuFile& f, const XmlElement& parent, std::string_view name,
                              const std::string& what) {
  if (const XmlElement* e = find_named_array(parent, name)) return *e;
  input_error(f.name, what + ": <" + parent.name + "> has no DataArray named " + std::string(name));
}

std::vector<vec3d> read_points(const VtuFile& f, const XmlElement& piece, uint64_t count, const std::string& what) {
  const std::string where = what + " Points";
  const XmlElement& array = required_child(f, required_child(f, piece, "Points", what), "DataArray", where);
  if (components_of(f, array, where) != 3) input_error(f.name, where + ": NumberOfComponents must be 3");
  const ScalarInfo type = numeric_type(f, array, where);
  if (!type.is_float) input_error(f.name, where + ": must be Float32 or Float64, not " + std::string(type.name));
  const std::vector<double> xyz = read_values<double>(f, array, type, count * 3, where);
  std::vector<vec3d> points(count);
  for (uint64_t i = 0; i < count; ++i) points[i] = vec3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
  return points;
}

std::vector<uint64_t> read_cell_array(const VtuFile& f, const XmlElement& cells, std::string_view name, uint64_t count,
                                      const std::string& what) {
  const std::string where = what + " " + std::string(name);
  const XmlElement& array = named_array(f, cells, name, what);
  return read_values<uint64_t>(f, array, numeric_type(f, array, where), count, where);
}

// Cells in MeshData's form: VTK's offsets are the ends of the cells; CSR adds a leading 0.
void read_cells(const VtuFile& f, const XmlElement& piece, uint64_t count, MeshData& mesh, const std::string& what) {
  const XmlElement& cells = required_child(f, piece, "Cells", what);
  const std::vector<uint64_t> ends = read_cell_array(f, cells, "offsets", count, what);
  for (uint64_t i = 1; i < count; ++i)
    if (ends[i] < ends[i - 1]) input_error(f.name, what + " offsets: decrease at cell " + str(i));
  mesh.connectivity = read_cell_array(f, cells, "connectivity", count ? ends.back() : 0, what);
  const std::vector<uint64_t> types = read_cell_array(f, cells, "types", count, what);
  mesh.cell_types.resize(count);
  for (uint64_t i = 0; i < count; ++i) {
    if (types[i] > 255) input_error(f.name, what + " types: " + str(types[i]) + " is not a VTK cell type");
    mesh.cell_types[i] = uint8_t(types[i]);
  }
  mesh.cell_offsets.assign(1, 0);
  mesh.cell_offsets.insert(mesh.cell_offsets.end(), ends.begin(), ends.end());
}

// The numeric arrays of <PointData> or <CellData>; other types (String, Bit) are skipped.
std::vector<MeshArray> read_attribute_arrays(const VtuFile& f, const XmlElement* section, uint64_t tuples,
                                             const std::string& what) {
  std::vector<MeshArray> arrays;
  if (!section) return arrays;
  for (const XmlElement& e : section->children) {
    if (e.name != "DataArray") continue;
    const std::string* name = e.attribute("Name");
    MeshArray a;
    a.name = name ? *name : "array" + std::to_string(arrays.size());
    const std::string where = what + " array '" + a.name + "'";
    const std::optional<ScalarInfo> type = scalar_info(required_attribute(f, e, "type", where));
    if (!type) continue;
    a.components = int(components_of(f, e, where));
    a.values = read_values<double>(f, e, *type, tuples * uint64_t(a.components), where);
    arrays.push_back(std::move(a));
  }
  return arrays;
}

// A cell array of point indices or face ids, as PolyhedronFaces holds them (saturated where one
// does not fit 32 bits: the split's range checks refuse it).
std::vector<FaceIndex> read_face_index_array(const VtuFile& f, const XmlElement& cells, std::string_view name,
                                             uint64_t count, const std::string& what) {
  const std::vector<uint64_t> wide = read_cell_array(f, cells, name, count, what);
  std::vector<FaceIndex> ids(wide.size());
  for (size_t i = 0; i < wide.size(); ++i) ids[i] = saturated_face_index(int64_t(wide[i]));  // 2^63 up: negative
  return ids;
}

// The faces of a piece's polyhedra (umesh/polyhedra.h), in either of VTK's layouts: VTK 9.4's
// four arrays (polyhedron_offsets: each cell's end in polyhedron_to_faces, whose face ids index
// face_offsets: each face's end in face_connectivity), or the face streams of the files before
// (faceoffsets: each cell's end in faces, -1 for a cell of another type). None without a polyhedron.
PolyhedronFaces read_polyhedron_faces(const VtuFile& f, const XmlElement& cells, const std::vector<uint8_t>& types,
                                      const std::string& what) {
  PolyhedronFaces faces;
  if (std::find(types.begin(), types.end(), kVtkPolyhedron) == types.end()) return faces;
  if (find_named_array(cells, "polyhedron_offsets")) {
    const std::vector<uint64_t> ends = read_cell_array(f, cells, "polyhedron_offsets", types.size(), what);
    faces.cell_face_offsets.insert(faces.cell_face_offsets.end(), ends.begin(), ends.end());
    faces.cell_faces = read_face_index_array(f, cells, "polyhedron_to_faces", ends.empty() ? 0 : ends.back(), what);
    const uint64_t face_count = faces.cell_faces.empty()
                                    ? 0
                                    : uint64_t(*std::max_element(faces.cell_faces.begin(), faces.cell_faces.end())) + 1;
    const std::vector<uint64_t> face_ends = read_cell_array(f, cells, "face_offsets", face_count, what);
    faces.face_offsets.insert(faces.face_offsets.end(), face_ends.begin(), face_ends.end());
    faces.face_vertices =
        read_face_index_array(f, cells, "face_connectivity", face_ends.empty() ? 0 : face_ends.back(), what);
    return faces;
  }
  const XmlElement& offsets_array = named_array(f, cells, "faceoffsets", what);
  const std::vector<int64_t> ends = read_values<int64_t>(
      f, offsets_array, numeric_type(f, offsets_array, what + " faceoffsets"), types.size(), what + " faceoffsets");
  uint64_t stream_end = 0;  // the largest end of a polyhedron's stream (VTK writes -1 for other cells)
  for (size_t c = 0; c < ends.size(); ++c)
    if (types[c] == kVtkPolyhedron)
      stream_end = std::max<uint64_t>(stream_end, uint64_t(std::max<int64_t>(ends[c], 0)));
  const std::vector<uint64_t> stream = read_cell_array(f, cells, "faces", stream_end, what);
  uint64_t begin = 0;
  for (size_t c = 0; c < types.size(); ++c) {
    if (types[c] != kVtkPolyhedron) {
      faces.add_other_cell();
      continue;
    }
    if (ends[c] < int64_t(begin))
      input_error(f.name, what + " faceoffsets: entry " + str(c) + " of a polyhedron is not the end of its faces");
    const uint64_t end = uint64_t(ends[c]);
    faces.add_face_stream(std::span(stream).subspan(begin, end - begin), c, f.name);
    begin = end;
  }
  return faces;
}

MeshData read_piece(const VtuFile& f, const XmlElement& piece, size_t index, SplitMemo* memo) {
  const std::string what = "Piece " + std::to_string(index);
  const uint64_t points = uint_attribute(f, piece, "NumberOfPoints", what);
  const uint64_t cells = uint_attribute(f, piece, "NumberOfCells", what);
  MeshData mesh;
  mesh.points = read_points(f, piece, points, what);
  read_cells(f, piece, cells, mesh, what);
  for (uint64_t i = 0; i < mesh.connectivity.size(); ++i)
    if (mesh.connectivity[i] >= points)
      input_error(f.name, what + ": connectivity entry " + str(i) + " = " + str(mesh.connectivity[i]) +
                              " is out of range (" + str(points) + " points)");
  mesh.point_data = read_attribute_arrays(f, piece.child("PointData"), points, what + " point");
  mesh.cell_data = read_attribute_arrays(f, piece.child("CellData"), cells, what + " cell");
  split_polyhedra(mesh, read_polyhedron_faces(f, required_child(f, piece, "Cells", what), mesh.cell_types, what),
                  f.name, memo);
  return mesh;
}

// The VTKFile attributes that say how binary data are stored, and its version.
void read_file_attributes(VtuFile& f) {
  const XmlElement& root = f.doc.root;
  if (root.name != "VTKFile") input_error(f.name, "not a VTK XML file (root element <" + root.name + ">)");
  const std::string* type = root.attribute("type");
  if (!type || *type != "UnstructuredGrid")
    input_error(f.name, "not a VTK UnstructuredGrid file (type \"" + (type ? *type : std::string()) + "\")");
  const std::string* order = root.attribute("byte_order");
  if (order && *order != "LittleEndian" && *order != "BigEndian") input_error(f.name, "unknown byte_order " + *order);
  const bool big = order && *order == "BigEndian";
  f.swap_bytes = big != (std::endian::native == std::endian::big);
  const std::string* header = root.attribute("header_type");
  if (header && *header != "UInt32" && *header != "UInt64") input_error(f.name, "unknown header_type " + *header);
  f.header_bytes = header && *header == "UInt64" ? 8 : 4;
  const std::string* version = root.attribute("version");
  f.pre_vtk91_lagrange = !version || version_below(*version, 2, 2);
  const std::string* compressor = root.attribute("compressor");
  if (compressor && !compressor->empty()) {
    const auto known = std::find_if(std::begin(kCompressors), std::end(kCompressors),
                                    [&](const CompressorInfo& c) { return c.name == *compressor; });
    if (known == std::end(kCompressors))
      input_error(f.name,
                  "unsupported compressor " + compressor->substr(0, 64) +
                      " (volstream reads vtkZLibDataCompressor, vtkLZ4DataCompressor and vtkLZMADataCompressor)");
    f.compressor = known->type;
  }
  if (f.doc.has_appended) {
    const std::string* encoding = f.doc.appended.attribute("encoding");
    if (!encoding || (*encoding != "raw" && *encoding != "base64"))
      input_error(f.name, "<AppendedData> encoding must be raw or base64");
    f.appended_base64 = *encoding == "base64";
    f.appended_end =
        f.appended_base64 ? std::min(f.text.find('<', f.doc.appended_begin), f.text.size()) : f.text.size();
  }
}

std::string read_whole_file(const fs::path& file) {
  const uint64_t size = file_size_checked(file, kMaxFileBytes);
  std::string text(size, '\0');
  read_exact(file, 0, text.data(), size);
  return text;
}

// The file's pieces joined (join_pieces), not yet checked with check_mesh; a file of one piece
// split with `memo`, if any.
MeshData read_vtu_unchecked(const fs::path& file, SplitMemo* memo) {
  VtuFile f;
  f.name = file.string();
  f.text = read_whole_file(file);
  f.doc = scan_xml(f.text, f.name);
  read_file_attributes(f);
  const XmlElement& grid = required_child(f, f.doc.root, "UnstructuredGrid", "VTKFile");
  const auto is_piece = [](const XmlElement& e) { return e.name == "Piece"; };
  if (std::count_if(grid.children.begin(), grid.children.end(), is_piece) != 1) memo = nullptr;
  std::vector<MeshData> pieces;
  for (const XmlElement& e : grid.children)
    if (is_piece(e)) pieces.push_back(read_piece(f, e, pieces.size(), memo));
  if (pieces.empty()) input_error(f.name, "the UnstructuredGrid has no <Piece>");
  if (f.pre_vtk91_lagrange)
    for (MeshData& piece : pieces) lagrange_hexahedra_from_pre_vtk91_order(piece);
  return join_pieces(std::move(pieces), f.name);
}

// The <TYPE> element of <VTKFile type="TYPE"> in a small VTK XML file that lists others (.pvd,
// .pvtu, .vtm); InputError `not_this` when the file is of another type.
XmlElement listing(const fs::path& file, const std::string& type, const std::string& not_this) {
  const std::string name = file.string();
  const std::string text = read_text_file(file);
  XmlDocument doc = scan_xml(text, name);
  const std::string* root_type = doc.root.attribute("type");
  if (doc.root.name != "VTKFile" || !root_type || *root_type != type) input_error(name, not_this);
  const auto body = std::find_if(doc.root.children.begin(), doc.root.children.end(),
                                 [&](const XmlElement& e) { return e.name == type; });
  if (body == doc.root.children.end()) input_error(name, "<VTKFile> has no <" + type + ">");
  return std::move(*body);
}

// The children of a listing named `entry`; InputError when there is none.
std::vector<XmlElement> listed_entries(const fs::path& file, const std::string& type, std::string_view entry,
                                       const std::string& not_this) {
  std::vector<XmlElement> entries;
  for (XmlElement& e : listing(file, type, not_this).children)
    if (e.name == entry) entries.push_back(std::move(e));
  if (entries.empty()) input_error(file.string(), "the " + type + " has no <" + std::string(entry) + "> entries");
  return entries;
}

// A path a list file names: relative ones from the list file's directory.
fs::path listed_path(const fs::path& list_file, const std::string& path) {
  const fs::path p(path);
  return p.is_absolute() ? p : list_file.parent_path() / p;
}

// The piece files a .pvtu names (<Piece Source=...>).
std::vector<fs::path> pvtu_sources(const fs::path& file) {
  std::vector<fs::path> sources;
  for (const XmlElement& e :
       listed_entries(file, "PUnstructuredGrid", "Piece", "not a VTK parallel unstructured grid (.pvtu) file")) {
    const std::string* source = e.attribute("Source");
    if (!source || source->empty())
      input_error(file.string(), "Piece " + std::to_string(sources.size()) + " has no Source");
    sources.push_back(listed_path(file, *source));
  }
  return sources;
}

// A <DataSet file=...> of a .vtm, and the names on the way down to it: its <Block>s' (and
// <Piece>s') and its own ("" for an element without a name).
struct VtmDataSet {
  fs::path file;
  std::vector<std::string> names;
};

// The data sets at any depth under `e`, in order.
void collect_datasets(const fs::path& vtm, const XmlElement& e, std::vector<std::string>& names,
                      std::vector<VtmDataSet>& datasets) {
  for (const XmlElement& child : e.children) {
    const std::string* name = child.attribute("name");
    names.push_back(name ? *name : "");
    const std::string* file = child.attribute("file");
    if (child.name == "DataSet" && file && !file->empty()) datasets.push_back({listed_path(vtm, *file), names});
    collect_datasets(vtm, child, names, datasets);
    names.pop_back();
  }
}

// The paths of a data set's names from the top ("fluid", "fluid/internal"), one per level.
std::vector<std::string> name_paths(const VtmDataSet& d) {
  std::vector<std::string> paths;
  std::string path;
  for (const std::string& name : d.names) {
    path += (path.empty() ? "" : "/") + name;
    paths.push_back(path);
  }
  return paths;
}

// Whether `wanted` names the data set or a block holding it: one of its names, or a path of
// them from the top, as ParaView shows the tree ("fluid/internal").
bool is_under(const VtmDataSet& d, const std::string& wanted) {
  const std::vector<std::string> paths = name_paths(d);
  return std::find(d.names.begin(), d.names.end(), wanted) != d.names.end() ||
         std::find(paths.begin(), paths.end(), wanted) != paths.end();
}

// The data sets under the blocks `wanted` names (all of them when it is empty); InputError for a
// name that matches none, listing the file's blocks.
std::vector<VtmDataSet> chosen_datasets(const fs::path& file, std::vector<VtmDataSet> all,
                                        const std::vector<std::string>& wanted) {
  if (wanted.empty()) return all;
  for (const std::string& w : wanted)
    if (std::none_of(all.begin(), all.end(), [&](const VtmDataSet& d) { return is_under(d, w); })) {
      std::vector<std::string> blocks;
      for (const VtmDataSet& d : all)
        for (const std::string& path : name_paths(d))
          if (std::find(blocks.begin(), blocks.end(), path) == blocks.end()) blocks.push_back(path);
      input_error(file.string(), "no block or data set '" + w + "' in this multiblock (its blocks: " +
                                     (blocks.empty() ? "none named" : joined(blocks)) + ")");
    }
  std::erase_if(all, [&](const VtmDataSet& d) {
    return std::none_of(wanted.begin(), wanted.end(), [&](const std::string& w) { return is_under(d, w); });
  });
  return all;
}

// The volume blocks of a .vtm, or of the blocks named in `wanted`: their .vtu and .pvtu files.
// Surfaces (.vtp, .pvtp: a CFD writer's boundary patches beside its volume mesh) are skipped;
// other data sets are refused.
std::vector<fs::path> vtm_volume_files(const fs::path& file, const std::vector<std::string>& wanted) {
  const std::string name = file.string();
  std::vector<VtmDataSet> all;
  std::vector<std::string> names;
  collect_datasets(file, listing(file, "vtkMultiBlockDataSet", "not a VTK multiblock (.vtm) file"), names, all);
  std::vector<fs::path> volumes;
  for (const VtmDataSet& d : chosen_datasets(file, std::move(all), wanted)) {
    const std::string ext = lower_extension(d.file);
    if (ext == ".vtu" || ext == ".pvtu")
      volumes.push_back(d.file);
    else if (ext != ".vtp" && ext != ".pvtp")
      input_error(name, "block " + d.file.filename().string().substr(0, 64) +
                            ": only unstructured grids (.vtu, .pvtu) and surfaces (.vtp, skipped) are read");
  }
  if (volumes.empty())
    input_error(name, std::string("no unstructured grid (.vtu or .pvtu) among its blocks") +
                          (wanted.empty() ? "" : " asked for (--region)"));
  return volumes;
}

// The files' meshes, read in parallel (a parallel run's output has a piece a rank); the error is
// the first bad file's, as in a serial loop.
std::vector<MeshData> read_each(const std::vector<fs::path>& files, MeshData (*read)(const fs::path&)) {
  std::vector<MeshData> meshes(files.size());
  parallel_each_in_order(int64_t(files.size()), [&](int64_t i) { meshes[size_t(i)] = read(files[size_t(i)]); });
  return meshes;
}

MeshData read_unsplit_vtu(const fs::path& file) { return read_vtu_unchecked(file, nullptr); }

MeshData read_pvtu_unchecked(const fs::path& file) {
  return join_pieces(read_each(pvtu_sources(file), read_unsplit_vtu), file.string());
}

MeshData read_block(const fs::path& file) {
  return lower_extension(file) == ".pvtu" ? read_pvtu_unchecked(file) : read_unsplit_vtu(file);
}

MeshData checked(MeshData mesh, const fs::path& file, SplitMemo* quadratic_memo = nullptr) {
  voxels_to_hexahedra(mesh);
  split_quadratic_cells(mesh, file.string(), quadratic_memo);
  check_mesh(mesh, file.string());
  return mesh;
}

}  // namespace

MeshData read_vtu(const std::filesystem::path& file, SeriesSplits* splits) {
  return checked(read_vtu_unchecked(file, splits ? &splits->polyhedra : nullptr), file,
                 splits ? &splits->quadratic : nullptr);
}

MeshData read_pvtu(const std::filesystem::path& file) { return checked(read_pvtu_unchecked(file), file); }

MeshData read_vtm(const std::filesystem::path& file, SeriesSplits* splits, const std::vector<std::string>& blocks) {
  const std::vector<fs::path> volumes = vtm_volume_files(file, blocks);
  if (volumes.size() == 1 && lower_extension(volumes.front()) == ".vtu")
    return checked(read_vtu_unchecked(volumes.front(), splits ? &splits->polyhedra : nullptr), file,
                   splits ? &splits->quadratic : nullptr);
  return checked(join_pieces(read_each(volumes, read_block), file.string(), MissingArrays::no_data), file);
}

// =============================================================================================
// Writing

namespace {

template <typename T>
void append_bytes(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// Values packed as the file's type, in host byte order; `max` guards narrowing of indices.
template <typename T, typename Range>
std::string pack(const Range& values, const char* what) {
  std::string out;
  out.reserve(values.size() * sizeof(T));
  for (const auto v : values) {
    if constexpr (std::is_integral_v<T>)
      if (uint64_t(v) > uint64_t(std::numeric_limits<T>::max()))
        throw std::invalid_argument(std::string("write_vtu: ") + what + " value " + std::to_string(v) +
                                    " does not fit the index type");
    append_bytes(out, T(v));
  }
  return out;
}

// One array's values as VTK writes them: type, name, components and the packed values.
struct OutArray {
  Scalar type;
  std::string name;
  int components;
  std::string bytes;
};

std::string ascii_text(const OutArray& a, const std::string& indent) {
  return with_scalar_type(a.type, [&](auto tag) {
    using T = decltype(tag);
    std::string out;
    char buffer[64];
    const size_t count = a.bytes.size() / sizeof(T);
    for (size_t i = 0; i < count; ++i) {
      out += i % 9 == 0 ? "\n" + indent : " ";
      const auto end =
          std::to_chars(buffer, buffer + sizeof(buffer), load<T>(a.bytes.data() + i * sizeof(T), false)).ptr;
      out.append(buffer, end);
    }
    return out + "\n" + indent.substr(2);
  });
}

class VtuWriter {
 public:
  VtuWriter(const VtuWriteOptions& options) : o_(options) {
    if (o_.compressor != VtuCompressor::none && o_.block_size == 0)
      throw std::invalid_argument("write_vtu: block_size must be > 0");
  }

  std::string document(const MeshData& mesh) {
    std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"";
    xml += std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
    xml += std::string("\" header_type=\"") + (o_.header_uint64 ? "UInt64" : "UInt32") + "\"";
    if (compressed()) xml += " compressor=\"" + std::string(compressor_info(o_.compressor).name) + "\"";
    xml += ">\n  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" + std::to_string(mesh.points.size()) +
           "\" NumberOfCells=\"" + std::to_string(mesh.cell_count()) + "\">\n";
    xml += section("PointData", data_arrays(mesh.point_data));
    xml += section("CellData", data_arrays(mesh.cell_data));
    xml += section("Points", {points_array(mesh)});
    xml += section("Cells", cell_arrays(mesh));
    xml += "    </Piece>\n  </UnstructuredGrid>\n";
    if (appended()) {
      xml += std::string("  <AppendedData encoding=\"") +
             (o_.format == VtuWriteOptions::Format::appended_raw ? "raw" : "base64") + "\">\n   _" + appended_ +
             "\n  </AppendedData>\n";
    }
    return xml + "</VTKFile>\n";
  }

 private:
  using Format = VtuWriteOptions::Format;
  bool appended() const { return o_.format == Format::appended_raw || o_.format == Format::appended_base64; }
  bool compressed() const { return o_.compressor != VtuCompressor::none && o_.format != Format::ascii; }

  std::vector<OutArray> data_arrays(const std::vector<MeshArray>& arrays) const {
    std::vector<OutArray> out;
    for (const MeshArray& a : arrays) out.push_back({Scalar::f32, a.name, a.components, pack<float>(a.values, "data")});
    return out;
  }

  OutArray points_array(const MeshData& mesh) const {
    std::vector<double> xyz;
    xyz.reserve(mesh.points.size() * 3);
    for (const vec3d& p : mesh.points) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    if (o_.points_float64) return {Scalar::f64, "Points", 3, pack<double>(xyz, "point")};
    return {Scalar::f32, "Points", 3, pack<float>(xyz, "point")};
  }

  OutArray index_array(const char* name, const std::vector<uint64_t>& values) const {
    if (o_.indices_int64) return {Scalar::i64, name, 1, pack<int64_t>(values, name)};
    return {Scalar::i32, name, 1, pack<int32_t>(values, name)};
  }

  std::vector<OutArray> cell_arrays(const MeshData& mesh) const {
    // VTK stores the end of each cell; MeshData's CSR offsets have a leading 0.
    const std::vector<uint64_t> ends(mesh.cell_offsets.begin() + (mesh.cell_offsets.empty() ? 0 : 1),
                                     mesh.cell_offsets.end());
    return {index_array("connectivity", mesh.connectivity),
            index_array("offsets", ends),
            {Scalar::u8, "types", 1, pack<uint8_t>(mesh.cell_types, "types")}};
  }

  std::string section(const char* name, const std::vector<OutArray>& arrays) {
    std::string xml = std::string("      <") + name + ">\n";
    for (const OutArray& a : arrays) xml += data_array(a);
    return xml + "      </" + name + ">\n";
  }

  std::string data_array(const OutArray& a) {
    std::string xml = "        <DataArray type=\"" + std::string(scalar_info(a.type).name) + "\" Name=\"" +
                      xml_escape(a.name) + "\" NumberOfComponents=\"" + std::to_string(a.components) + "\" format=\"";
    switch (o_.format) {
      case Format::ascii:
        return xml + "ascii\">" + ascii_text(a, "          ") + "</DataArray>\n";
      case Format::base64:
        return xml + "binary\">\n          " + encoded(a.bytes, true) + "\n        </DataArray>\n";
      case Format::appended_base64:
      case Format::appended_raw:
        break;
    }
    xml += "appended\" offset=\"" + std::to_string(appended_.size()) + "\"/>\n";
    appended_ += encoded(a.bytes, o_.format == Format::appended_base64);
    return xml;
  }

  void append_header_word(std::string& out, uint64_t v) const {
    if (o_.header_uint64) return append_bytes(out, v);
    if (v > UINT32_MAX) throw std::invalid_argument("write_vtu: an array is too large for a UInt32 header");
    append_bytes(out, uint32_t(v));
  }

  // Header and data; with base64 each is encoded on its own, as VTK does (its readers decode the
  // header before they know where the data begin).
  std::string encoded(const std::string& bytes, bool base64) const {
    std::string header, data;
    if (compressed()) {
      compress_blocks(bytes, header, data);
    } else {
      append_header_word(header, bytes.size());
      data = bytes;
    }
    return base64 ? base64_encode(header) + base64_encode(data) : header + data;
  }

  void compress_blocks(const std::string& bytes, std::string& header, std::string& data) const {
    const uint64_t block = o_.block_size;
    const uint64_t blocks = (bytes.size() + block - 1) / block;
    append_header_word(header, blocks);
    append_header_word(header, block);
    append_header_word(header, bytes.size() % block);  // 0: the last block is full
    for (uint64_t b = 0; b < blocks; ++b) {
      const uint64_t size = std::min<uint64_t>(block, bytes.size() - b * block);
      const size_t before = data.size();
      encode_block(o_.compressor, std::string_view(bytes).substr(b * block, size), data);
      append_header_word(header, data.size() - before);
    }
  }

  // One block compressed onto the end of `out`, at each library's default level (as VTK's 5).
  static void encode_block(VtuCompressor type, std::string_view in, std::string& out) {
    const size_t at = out.size();
    size_t packed = 0;
    bool ok = false;
    if (type == VtuCompressor::zlib) {
      uLongf n = compressBound(uLong(in.size()));
      out.resize(at + n);
      ok = compress2(reinterpret_cast<Bytef*>(out.data() + at), &n, reinterpret_cast<const Bytef*>(in.data()),
                     uLong(in.size()), Z_DEFAULT_COMPRESSION) == Z_OK;
      packed = n;
    } else if (type == VtuCompressor::lz4) {
      if (in.size() > LZ4_MAX_INPUT_SIZE) throw std::invalid_argument("write_vtu: block too large for LZ4");
      out.resize(at + size_t(LZ4_compressBound(int(in.size()))));
      const int n = LZ4_compress_default(in.data(), out.data() + at, int(in.size()), int(out.size() - at));
      ok = n > 0 || in.empty();
      packed = size_t(std::max(n, 0));
    } else {
      out.resize(at + lzma_stream_buffer_bound(in.size()));
      size_t end = at;  // liblzma writes from out[end] on and moves end past what it wrote
      ok = lzma_easy_buffer_encode(5, LZMA_CHECK_CRC64, nullptr, reinterpret_cast<const uint8_t*>(in.data()), in.size(),
                                   reinterpret_cast<uint8_t*>(out.data()), &end, out.size()) == LZMA_OK;
      packed = end - at;
    }
    if (!ok) throw std::runtime_error("write_vtu: compression failed");
    out.resize(at + packed);
  }

  const VtuWriteOptions& o_;
  std::string appended_;
};

void write_text_atomic(const fs::path& file, const std::string& text) {
  AtomicFile out(file);
  out.write(text);
  out.commit();
}

}  // namespace

void write_vtu(const std::filesystem::path& file, const MeshData& mesh, const VtuWriteOptions& options) {
  write_text_atomic(file, VtuWriter(options).document(mesh));
}

void write_pvtu(const std::filesystem::path& file, const std::vector<MeshData>& pieces,
                const VtuWriteOptions& options) {
  if (pieces.empty()) throw std::invalid_argument("write_pvtu: no pieces");
  std::string xml =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\">\n"
      "  <PUnstructuredGrid GhostLevel=\"0\">\n";
  auto declare = [&](const char* section, const std::vector<MeshArray>& arrays) {
    xml += std::string("    <") + section + ">\n";
    for (const MeshArray& a : arrays)
      xml += "      <PDataArray type=\"Float32\" Name=\"" + xml_escape(a.name) + "\" NumberOfComponents=\"" +
             std::to_string(a.components) + "\"/>\n";
    xml += std::string("    </") + section + ">\n";
  };
  declare("PPointData", pieces.front().point_data);
  declare("PCellData", pieces.front().cell_data);
  xml += std::string("    <PPoints>\n      <PDataArray type=\"") + (options.points_float64 ? "Float64" : "Float32") +
         "\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
  for (size_t i = 0; i < pieces.size(); ++i) {
    const fs::path piece = file.stem().string() + "_" + std::to_string(i) + ".vtu";
    write_vtu(file.parent_path() / piece, pieces[i], options);
    xml += "    <Piece Source=\"" + xml_escape(piece.generic_string()) + "\"/>\n";
  }
  write_text_atomic(file, xml + "  </PUnstructuredGrid>\n</VTKFile>\n");
}

// =============================================================================================
// ParaView collections

namespace {

double parse_time(const std::string& file, const std::string& text, size_t index) {
  double t = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), t);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty() || !std::isfinite(t))
    input_error(file, "DataSet " + std::to_string(index) + ": bad timestep \"" + text.substr(0, 32) + "\"");
  return t;
}

// One <DataSet> entry: a part of a time step.
struct PvdEntry {
  double time;
  uint64_t part;
  fs::path file;
};

PvdEntry read_dataset(const fs::path& file, const XmlElement& e, size_t index) {
  const std::string name = file.string();
  const std::string what = "DataSet " + std::to_string(index);
  const std::string* time = e.attribute("timestep");
  const std::string* path = e.attribute("file");
  const std::string* part = e.attribute("part");
  if (!time) input_error(name, what + " has no timestep attribute");
  if (!path || path->empty()) input_error(name, what + " has no file attribute");
  uint64_t part_number = 0;
  if (part && !part->empty()) {
    const auto [end, ec] = std::from_chars(part->data(), part->data() + part->size(), part_number);
    if (ec != std::errc() || end != part->data() + part->size())
      input_error(name, what + ": bad part \"" + part->substr(0, 32) + "\"");
  }
  return {parse_time(name, *time, index), part_number, listed_path(file, *path)};
}

}  // namespace

namespace {

// Entries as steps: sorted by time, the entries of one time its parts in part order.
std::vector<PvdStep> steps_of(std::vector<PvdEntry> entries, const std::string& name) {
  std::stable_sort(entries.begin(), entries.end(), [](const PvdEntry& a, const PvdEntry& b) {
    return a.time != b.time ? a.time < b.time : a.part < b.part;
  });
  std::vector<PvdStep> steps;
  for (size_t i = 0; i < entries.size(); ++i) {
    const bool same_time = i > 0 && entries[i].time == entries[i - 1].time;
    if (same_time && entries[i].part == entries[i - 1].part)
      input_error(name, "two entries have time " + std::to_string(entries[i].time) + " and part " +
                            std::to_string(entries[i].part));
    if (!same_time) steps.push_back({entries[i].time, {}});
    steps.back().parts.push_back(entries[i].file);
  }
  return steps;
}

// One entry of a file series' "files": {"name": FILE, "time": T}.
PvdEntry series_entry(const fs::path& file, const nlohmann::json& e, size_t index) {
  const std::string what = "files[" + std::to_string(index) + "]";
  if (!e.is_object() || !e.contains("name") || !e["name"].is_string() || e["name"].get<std::string>().empty())
    input_error(file.string(), what + " has no name");
  if (!e.contains("time") || !e["time"].is_number() || !std::isfinite(e["time"].get<double>()))
    input_error(file.string(), what + " has no finite time");
  return {e["time"].get<double>(), 0, listed_path(file, e["name"].get<std::string>())};
}

}  // namespace

std::vector<PvdStep> read_pvd(const std::filesystem::path& file) {
  std::vector<PvdEntry> entries;
  for (const XmlElement& e : listed_entries(file, "Collection", "DataSet", "not a VTK Collection (.pvd) file"))
    entries.push_back(read_dataset(file, e, entries.size()));
  return steps_of(std::move(entries), file.string());
}

std::vector<PvdStep> read_file_series(const std::filesystem::path& file) {
  const std::string name = file.string();
  const nlohmann::json doc = nlohmann::json::parse(read_text_file(file), nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) input_error(name, "not a JSON file series (.series)");
  if (doc.contains("file-series-version") && doc["file-series-version"] != "1.0") {
    // (dump() cannot meet bad UTF-8 here: parse refused it.)
    const std::string version = doc["file-series-version"].dump();
    input_error(name, "file-series-version " + version.substr(0, 32) + " (volstream reads 1.0)");
  }
  if (!doc.contains("files") || !doc["files"].is_array() || doc["files"].empty())
    input_error(name, "no \"files\" entries");
  std::vector<PvdEntry> entries;
  for (const nlohmann::json& e : doc["files"]) entries.push_back(series_entry(file, e, entries.size()));
  return steps_of(std::move(entries), name);
}

void write_pvd(const std::filesystem::path& file, const std::vector<PvdStep>& steps) {
  const fs::path dir = fs::absolute(file).parent_path().lexically_normal();
  std::string xml =
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const PvdStep& s : steps) {
    char time[64];
    const auto end = std::to_chars(time, time + sizeof(time), s.time).ptr;
    for (size_t part = 0; part < s.parts.size(); ++part) {
      const fs::path absolute = fs::absolute(s.parts[part]).lexically_normal();
      const fs::path relative = absolute.lexically_relative(dir);
      xml += "    <DataSet timestep=\"" + std::string(time, end) + "\" group=\"\" part=\"" + std::to_string(part) +
             "\" file=\"" + xml_escape((relative.empty() ? absolute : relative).generic_string()) + "\"/>\n";
    }
  }
  write_text_atomic(file, xml + "  </Collection>\n</VTKFile>\n");
}

}  // namespace vs
