#include "volstream/io/openfoam.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <string_view>

#include "volstream/core/error.h"
#include "volstream/core/release.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/byte_order.h"
#include "volstream/io/parse_cursor.h"
#include "volstream/umesh/polyhedra.h"

namespace vs {
namespace fs = std::filesystem;

namespace {

// The number after `prefix` in a directory's name ("processor12": 12), as OpenFOAM writes it (no
// sign, no leading zeros); nullopt for any other name.
std::optional<uint64_t> number_after(const std::string& name, std::string_view prefix) {
  const std::string_view digits = std::string_view(name).substr(std::min(name.size(), prefix.size()));
  if (!name.starts_with(prefix) || digits.empty() ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  uint64_t number = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), number);
  if (error != std::errc() || std::to_string(number) != digits) return std::nullopt;
  return number;
}

// A collated decomposed case (decomposePar -fileHandler collated) keeps every processor's
// files in one directory, processors<N>: each of its files holds the N processors' files one
// after another. Its processor k is read here through the path processors<N>/processor<k>/...,
// which names block k of the file processors<N>/... .
struct OnDisk {
  fs::path path;
  std::optional<uint64_t> block;
  uint64_t processors = 0;  // N of processors<N>, for a block
};
OnDisk on_disk(const fs::path& p) {
  OnDisk d;
  bool in_collated = false;
  for (const fs::path& part : p) {
    const std::string name = part.string();
    if (in_collated && !d.block && (d.block = number_after(name, "processor"))) continue;
    const std::optional<uint64_t> processors = number_after(name, "processors");
    in_collated = processors.has_value();
    if (in_collated && !d.block) d.processors = *processors;
    d.path /= part;
  }
  return d;
}

// `dir/name`, or `dir/name.gz` where only that exists (writeCompression on); nullopt for neither.
std::optional<fs::path> find_file(const fs::path& dir, const std::string& name) {
  std::error_code ec;
  for (const std::string& n : {name, name + ".gz"})
    if (fs::is_regular_file(on_disk(dir / n).path, ec)) return dir / n;
  return std::nullopt;
}

// A FoamFile header: how the rest of the file is written.
struct Header {
  bool binary = false, big_endian = false;
  int label_bytes = 4, scalar_bytes = 8;
  std::string class_name, note;
};

// OpenFOAM's files: a FoamFile header dictionary, then entries (fields) or one list (mesh
// files). ParseCursor's binary reads and size checks, with OpenFOAM's tokens on top: words end at
// punctuation as well as at spaces, and // and /* */ comments are space. Failures name the offset.
class Cursor : public ParseCursor {
 public:
  using ParseCursor::ParseCursor;

  [[noreturn]] void fail(const std::string& what) const {
    ParseCursor::fail("offset " + std::to_string(position()) + ": " + what);
  }

  void skip_space_and_comments() {
    for (;;) {
      skip_space();
      const std::string_view r = rest();
      if (r.starts_with("//")) {
        skip_line();
      } else if (r.starts_with("/*")) {
        seek(position() + 2);
        if (!skip_past("*/")) fail("a /* comment is not closed before the end of the file");
      } else {
        return;
      }
    }
  }
  bool at_end() {
    skip_space_and_comments();
    return remaining() == 0;
  }
  bool peek(char c) {
    skip_space_and_comments();
    return !rest().empty() && rest().front() == c;
  }
  void expect(char c, const char* where) {
    if (!peek(c)) fail(std::string("expected '") + c + "' " + where + (remaining() ? "" : " (the file ends)"));
    seek(position() + 1);
  }
  // A word (up to a space, a punctuation character or a comment), a string in double quotes
  // (without them), or one punctuation character; empty at the end of the file.
  std::string_view token() {
    skip_space_and_comments();
    const std::string_view r = rest();
    if (r.empty()) return r;
    if (r.front() == '"') {
      size_t n = 1;
      while (n < r.size() && r[n] != '"') n += r[n] == '\\' ? 2 : 1;
      if (n >= r.size()) fail("a string in double quotes is not closed before the end of the file");
      seek(position() + n + 1);
      return r.substr(1, n - 1);
    }
    if (is_punct(r.front())) {
      seek(position() + 1);
      return r.substr(0, 1);
    }
    size_t n = 0;
    while (n < r.size() && !std::isspace(static_cast<unsigned char>(r[n])) && !is_punct(r[n]) &&
           !r.substr(n).starts_with("//") && !r.substr(n).starts_with("/*"))
      ++n;
    seek(position() + n);
    return r.substr(0, n);
  }
  int64_t label(const char* what) {
    const std::string_view t = token();
    int64_t v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || ec != std::errc() || end != t.data() + t.size()) {
      seek(position() - t.size());
      fail(std::string("expected an integer (") + what + ")");
    }
    return v;
  }
  double scalar(const char* what) {
    const std::string_view t = token();
    double v = 0;
    const char* first = t.data() + (t.size() > 1 && t[0] == '+' ? 1 : 0);
    const auto [end, ec] = std::from_chars(first, t.data() + t.size(), v);
    if (t.empty() || (ec != std::errc() && ec != std::errc::result_out_of_range) || end != t.data() + t.size()) {
      seek(position() - t.size());
      fail(std::string("expected a number (") + what + ")");
    }
    // from_chars leaves v alone out of range: strtod gives the subnormal, zero or infinity (the
    // last refused when convert writes the values).
    if (ec == std::errc::result_out_of_range) v = std::strtod(std::string(t).c_str(), nullptr);
    return v;
  }

  // Past the entry whose keyword is behind us: a dictionary "{ ... }", or tokens up to the ';'
  // outside parentheses and brackets.
  void skip_entry() {
    if (peek('{')) {
      seek(position() + 1);
      return skip_block('{', '}');
    }
    int depth = 0;
    for (;;) {
      const std::string_view t = token();
      if (t.empty()) fail("an entry is not closed by ';' before the end of the file");
      if (t == "(" || t == "[") ++depth;
      if ((t == ")" || t == "]") && --depth < 0) fail("unbalanced parentheses");
      if (t == ";" && depth == 0) return;
    }
  }
  void skip_block(char open, char close) {
    for (int depth = 1;;) {
      const std::string_view t = token();
      if (t.empty()) fail(std::string("unbalanced braces: a '") + open + "' is not closed before the end of the file");
      if (t.size() == 1 && t[0] == open) ++depth;
      if (t.size() == 1 && t[0] == close && --depth == 0) return;
    }
  }

  Header header() {
    if (token() != "FoamFile") fail("expected the FoamFile header");
    expect('{', "opening the FoamFile header");
    Header h;
    std::string format;
    for (;;) {
      const std::string key(token());
      if (key.empty()) fail("the FoamFile header is not closed before the end of the file");
      if (key == "}") break;
      std::string value;
      for (std::string_view t; (t = token()) != ";";) {
        if (t.empty() || t == "}") fail("the FoamFile header's entry " + key + " is not closed by ';'");
        value += (value.empty() ? "" : " ") + std::string(t);
      }
      if (key == "format") format = value;
      if (key == "class") h.class_name = value;
      if (key == "note") h.note = value;
      if (key == "arch") arch(value, h);
    }
    if (format != "ascii" && format != "binary") fail("unknown format '" + format + "' (ascii or binary)");
    h.binary = format == "binary";
    return h;
  }

 private:
  static bool is_punct(char c) {
    return c == '(' || c == ')' || c == '{' || c == '}' || c == '[' || c == ']' || c == ';' || c == '"';
  }
  // "LSB;label=32;scalar=64"
  void arch(const std::string& value, Header& h) {
    h.big_endian = value.find("MSB") != std::string::npos;
    for (const auto& [key, bytes] : {std::pair{"label=", &h.label_bytes}, std::pair{"scalar=", &h.scalar_bytes}}) {
      const size_t at = value.find(key);
      if (at == std::string::npos) continue;
      const std::string bits = value.substr(at + std::string_view(key).size(), 2);
      if (bits != "32" && bits != "64") fail("arch \"" + value + "\": labels and scalars are 32 or 64 bits");
      *bytes = bits == "32" ? 4 : 8;
    }
  }
};

// A label as Label: int64_t as it is; a FaceIndex (face vertices, which the caller checks against
// the point count) saturated, so that a negative label or one past 32 bits is out of range.
template <typename Label>
Label label_as(int64_t v) {
  if constexpr (std::is_same_v<Label, FaceIndex>)
    return saturated_face_index(v);
  else
    return Label(v);
}

// `n` binary values of type T from one block of the file, each as Out: the block is taken and
// checked once, then decoded in a loop without a check per value (a mesh's faces are tens of
// millions of labels).
template <typename T, typename Out>
void decode_block(Cursor& in, bool big_endian, uint64_t n, Out* out, const char* what) {
  load_values<T>(in.take(n * sizeof(T), what), n, big_endian, out);
}

// decode_block for labels of type T, each as Label (label_as), through a small buffer.
template <typename T, typename Label>
void decode_labels(Cursor& in, bool big_endian, uint64_t n, Label* out, const char* what) {
  if constexpr (!std::is_same_v<Label, FaceIndex>) {
    decode_block<T>(in, big_endian, n, out, what);
  } else {
    const char* bytes = in.take(n * sizeof(T), what);
    constexpr uint64_t kChunk = 4096;
    int64_t labels[kChunk];
    for (uint64_t first = 0; first < n; first += kChunk) {
      const uint64_t count = std::min(kChunk, n - first);
      load_values<T>(bytes + first * sizeof(T), count, big_endian, labels);
      for (uint64_t i = 0; i < count; ++i) out[first + i] = label_as<Label>(labels[i]);
    }
  }
}

// A list of labels, "N ( a b ... )" or "N { a }" (uniform), ascii or binary as `h` says; each as
// Label (label_as).
template <typename Label = int64_t>
std::vector<Label> read_labels(Cursor& in, const Header& h, const char* what) {
  const int64_t n = in.label(what);
  if (n < 0) in.fail(std::string("a negative count of ") + what);
  if (in.peek('{')) {
    in.seek(in.position() + 1);
    in.require_fits(uint64_t(n) / 64, 1, what);  // a uniform list of labels, in a mesh file, is short
    const int64_t v = in.label(what);
    in.expect('}', "closing a uniform list");
    return std::vector<Label>(size_t(n), label_as<Label>(v));
  }
  in.expect('(', "opening a list");
  std::vector<Label> v;
  if (h.binary) {
    in.require_fits(uint64_t(n), uint64_t(h.label_bytes), what);
    v.resize(size_t(n));
    if (h.label_bytes == 4)
      decode_labels<int32_t>(in, h.big_endian, uint64_t(n), v.data(), what);
    else
      decode_labels<int64_t>(in, h.big_endian, uint64_t(n), v.data(), what);
  } else {
    in.require_fits(uint64_t(n), 2, what);
    v.resize(size_t(n));
    for (Label& x : v) x = label_as<Label>(in.label(what));
  }
  in.expect(')', "closing a list");
  return v;
}

// A list of `components` scalars each ("N ( a b ... )", or of vectors "N ( (x y z) ... )"), or
// "N { v }"; `expected` items where it is given (a field's cell count).
std::vector<double> read_scalars(Cursor& in, const Header& h, int components, std::optional<uint64_t> expected,
                                 const char* what) {
  const int64_t n = in.label(what);
  if (n < 0) in.fail(std::string("a negative count of ") + what);
  if (expected && uint64_t(n) != *expected)
    in.fail(std::string("a list of ") + std::to_string(n) + " " + what + ", not " + std::to_string(*expected));
  const auto item = [&](double* out) {
    if (components == 1) {
      *out = in.scalar(what);
      return;
    }
    in.expect('(', "opening a vector");
    for (int k = 0; k < components; ++k) out[k] = in.scalar(what);
    in.expect(')', "closing a vector");
  };
  std::vector<double> v;
  if (in.peek('{')) {
    in.seek(in.position() + 1);
    if (!expected) in.require_fits(uint64_t(n) / 64, 1, what);
    double one[3] = {};
    item(one);
    in.expect('}', "closing a uniform list");
    v.resize(size_t(n) * size_t(components));
    for (size_t i = 0; i < v.size(); ++i) v[i] = one[i % size_t(components)];
    return v;
  }
  in.expect('(', "opening a list");
  if (h.binary) {
    in.require_fits(uint64_t(n), uint64_t(h.scalar_bytes) * uint64_t(components), what);
    v.resize(size_t(n) * size_t(components));
    if (h.scalar_bytes == 4)
      decode_block<float>(in, h.big_endian, v.size(), v.data(), what);
    else
      decode_block<double>(in, h.big_endian, v.size(), v.data(), what);
  } else {
    in.require_fits(uint64_t(n), components == 1 ? 2 : 7, what);
    v.resize(size_t(n) * size_t(components));
    for (int64_t i = 0; i < n; ++i) item(&v[size_t(i) * size_t(components)]);
  }
  in.expect(')', "closing a list");
  return v;
}

// The mesh of constant/polyMesh (or a decomposed case's processors' meshes joined).
struct PolyMesh {
  std::vector<vec3d> points;
  std::vector<uint64_t> face_offsets{0};  // with face_vertices, moved to the PolyhedronFaces once read
  std::vector<FaceIndex> face_vertices;
  // Dropped once the cells' faces are built. A face past the neighbours, or whose neighbour is
  // -1 (a joined mesh's), has its owner alone.
  std::vector<int64_t> owner, neighbour;
  uint64_t cell_count = 0;
  fs::path owner_file;
};

// Reads the case's files: whole, or a processor's block of a collated file (on_disk). A
// collated file (class decomposedBlockData) is a FoamFile header, then for each processor
// "// ProcessorK", its block's size in bytes and the block in parentheses; the first block is a
// whole file, FoamFile header and all, the others the rest of a file after that header (OpenFOAM
// writes it once), read here after a header of the same format, class and arch. A collated file is read once and kept
// until forget(), so that the N processors' blocks of one file cost one read.
class CaseFiles {
 public:
  std::string read(const fs::path& file) {
    const OnDisk d = on_disk(file);
    if (!d.block) return read_file_inflating(d.path);
    auto it = collated_.find(d.path);
    if (it == collated_.end()) it = collated_.emplace(d.path, split(d.path, d.processors)).first;
    Collated& c = it->second;
    const auto [at, size] = c.blocks.at(*d.block);
    c.in.seek(at);
    std::string bytes = *d.block == 0 ? std::string() : c.header;
    bytes += c.in.rest().substr(0, size);
    return bytes;
  }
  // The file's first `limit` bytes at most (of a collated file, those of its first block),
  // enough for its FoamFile header; empty for a collated file whose first block is not there.
  static std::string start(const fs::path& file, size_t limit) {
    const OnDisk d = on_disk(file);
    std::string bytes = read_file_inflating(d.path, limit);
    if (!d.block) return bytes;
    Cursor in(std::move(bytes), d.path.string());
    try {
      in.header();
      in.label("a processor's block size");
      in.expect('(', "opening a processor's block");
      return std::string(in.rest());
    } catch (const InputError&) {
      return {};
    }
  }
  void forget() { collated_.clear(); }

 private:
  struct Collated {
    Cursor in;  // the whole file
    std::string header;
    std::vector<std::pair<uint64_t, uint64_t>> blocks;  // offset and size
  };
  static Collated split(const fs::path& file, uint64_t processors) {
    Collated c{Cursor(read_file_inflating(file), file.string()), {}, {}};
    Cursor& in = c.in;
    const Header h = in.header();
    if (h.class_name != "decomposedBlockData")
      in.fail("class '" + h.class_name + "', not decomposedBlockData (a collated case's file of every processor)");
    for (uint64_t k = 0; k < processors; ++k) {
      const int64_t size = in.label("a processor's block size");
      if (size < 0) in.fail("a processor's block of " + std::to_string(size) + " bytes");
      in.expect('(', "opening a processor's block");
      c.blocks.push_back({in.position(), uint64_t(size)});
      in.take(uint64_t(size), "a processor's block");
      in.expect(')', "closing a processor's block");
    }
    if (!in.at_end())
      in.fail("more than the " + std::to_string(processors) + " processors' blocks that the directory's name counts");
    // The other blocks' header: the first block's, without its note (whose counts, as an
    // owner file's nCells, are the first processor's).
    in.seek(c.blocks.front().first);
    Cursor first(std::string(in.rest().substr(0, c.blocks.front().second)), file.string() + " (processor0's block)");
    const Header h0 = first.header();
    c.header = std::string("FoamFile\n{\n    format      ") + (h0.binary ? "binary" : "ascii") + ";\n    class       " +
               h0.class_name + ";\n    arch        \"" + (h0.big_endian ? "MSB" : "LSB") +
               ";label=" + std::to_string(8 * h0.label_bytes) + ";scalar=" + std::to_string(8 * h0.scalar_bytes) +
               "\";\n}\n";
    return c;
  }
  std::map<fs::path, Collated> collated_;
};

Cursor open_mesh_file(CaseFiles& files, const fs::path& dir, const char* name, Header& h) {
  const std::optional<fs::path> file = find_file(dir, name);
  if (!file) input_error((dir / name).string(), "missing: an OpenFOAM mesh is points, faces, owner and neighbour");
  Cursor in(files.read(*file), file->string());
  h = in.header();
  return in;
}
void expect_end(Cursor& in) {
  if (!in.at_end()) in.fail("more after the list");
}

// A mesh file that is one labelList (owner, neighbour, pointProcAddressing).
std::vector<int64_t> read_label_list(Cursor& in, const Header& h, const char* what) {
  if (h.class_name != "labelList") in.fail("class '" + h.class_name + "', not labelList");
  std::vector<int64_t> labels = read_labels(in, h, what);
  expect_end(in);
  return labels;
}

std::vector<vec3d> read_points(CaseFiles& files, const fs::path& dir) {
  Header h;
  Cursor in = open_mesh_file(files, dir, "points", h);
  if (h.class_name != "vectorField") in.fail("class '" + h.class_name + "', not vectorField");
  const std::vector<double> xyz = read_scalars(in, h, 3, std::nullopt, "points");
  expect_end(in);
  std::vector<vec3d> points(xyz.size() / 3);
  for (size_t p = 0; p < points.size(); ++p) points[p] = {xyz[3 * p], xyz[3 * p + 1], xyz[3 * p + 2]};
  return points;
}

void add_face(Cursor& in, PolyMesh& m, uint64_t face, uint64_t vertices) {
  if (vertices < 3) in.fail("face " + std::to_string(face) + " of " + std::to_string(vertices) + " vertices");
  m.face_offsets.push_back(m.face_offsets.back() + vertices);
}
[[noreturn]] void vertex_out_of_range(Cursor& in, const PolyMesh& m, uint64_t face, int64_t v) {
  in.fail("face " + std::to_string(face) + ": point " + std::to_string(v) + " out of range 0.." +
          std::to_string(m.points.size() - 1));
}
void add_vertex(Cursor& in, PolyMesh& m, uint64_t face, int64_t v) {
  if (v < 0 || uint64_t(v) >= m.points.size()) vertex_out_of_range(in, m, face, v);
  m.face_vertices.push_back(saturated_face_index(v));  // a point count past 32 bits is refused by the split
}

// faceCompactList: the offsets (faces + 1), then every face's vertices; faceList: "N ( n(a b c)
// ... )", each face a list of its own (in binary files too).
void read_faces(CaseFiles& files, const fs::path& dir, PolyMesh& m) {
  Header h;
  Cursor in = open_mesh_file(files, dir, "faces", h);
  if (h.class_name == "faceCompactList") {
    const std::vector<int64_t> offsets = read_labels(in, h, "face offsets");
    m.face_vertices = read_labels<FaceIndex>(in, h, "face vertices");  // checked below
    expect_end(in);
    if (offsets.empty() || offsets.front() != 0 || uint64_t(offsets.back()) != m.face_vertices.size())
      in.fail("the face offsets do not span the " + std::to_string(m.face_vertices.size()) + " face vertices");
    m.face_offsets.reserve(offsets.size());
    for (size_t f = 0; f + 1 < offsets.size(); ++f) {
      if (offsets[f + 1] < offsets[f]) in.fail("the face offsets decrease at face " + std::to_string(f));
      add_face(in, m, f, uint64_t(offsets[f + 1] - offsets[f]));
    }
    const auto out_of_range =
        std::find_if(m.face_vertices.begin(), m.face_vertices.end(), [&](uint64_t v) { return v >= m.points.size(); });
    if (out_of_range != m.face_vertices.end()) {
      const auto k = uint64_t(out_of_range - m.face_vertices.begin());
      const auto face =
          uint64_t(std::upper_bound(m.face_offsets.begin(), m.face_offsets.end(), k) - m.face_offsets.begin()) - 1;
      vertex_out_of_range(in, m, face, int64_t(*out_of_range));
    }
    return;
  }
  if (h.class_name != "faceList") in.fail("class '" + h.class_name + "', not faceList or faceCompactList");
  const int64_t n = in.label("the face count");
  if (n < 0) in.fail("a negative face count");
  in.expect('(', "opening the faces");
  in.require_fits(uint64_t(n), h.binary ? 3 * uint64_t(h.label_bytes) : 8, "faces");
  m.face_offsets.reserve(size_t(n) + 1);
  m.face_vertices.reserve(4 * size_t(n));  // quads, the common face: no doubling (the count fits the file)
  for (int64_t f = 0; f < n; ++f) {
    const int64_t vertices = in.label("a face's vertex count");
    if (vertices < 3) in.fail("face " + std::to_string(f) + " of " + std::to_string(vertices) + " vertices");
    in.require_fits(uint64_t(vertices), h.binary ? uint64_t(h.label_bytes) : 2, "face vertices");
    in.expect('(', "opening a face");
    for (int64_t k = 0; k < vertices; ++k) {
      const int64_t v = h.label_bytes == 4 && h.binary ? int64_t(in.binary<int32_t>(h.big_endian, "face vertices"))
                        : h.binary                     ? in.binary<int64_t>(h.big_endian, "face vertices")
                                                       : in.label("a face vertex");
      add_vertex(in, m, uint64_t(f), v);
    }
    in.expect(')', "closing a face");
    add_face(in, m, uint64_t(f), uint64_t(vertices));
  }
  in.expect(')', "closing the faces");
  expect_end(in);
}

// "nCells:729" in an owner file's note.
std::optional<uint64_t> note_count(const std::string& note, const std::string& key) {
  const size_t at = note.find(key + ":");
  if (at == std::string::npos) return std::nullopt;
  uint64_t v = 0;
  const char* first = note.data() + at + key.size() + 1;
  const auto [end, ec] = std::from_chars(first, note.data() + note.size(), v);
  if (ec != std::errc() || end == first) return std::nullopt;
  return v;
}

void read_owners(CaseFiles& files, const fs::path& dir, PolyMesh& m) {
  const uint64_t faces = m.face_offsets.size() - 1;
  Header h;
  Cursor owner = open_mesh_file(files, dir, "owner", h);
  m.owner = read_label_list(owner, h, "owners");
  m.owner_file = owner.file();
  if (m.owner.size() != faces)
    owner.fail(std::to_string(m.owner.size()) + " owners of " + std::to_string(faces) + " faces");
  const std::optional<uint64_t> declared = note_count(h.note, "nCells");

  Header hn;
  Cursor neighbour = open_mesh_file(files, dir, "neighbour", hn);
  m.neighbour = read_label_list(neighbour, hn, "neighbours");
  if (m.neighbour.size() > faces)
    neighbour.fail(std::to_string(m.neighbour.size()) + " neighbours of " + std::to_string(faces) + " faces");

  int64_t last = -1;
  for (const std::vector<int64_t>* list : {&m.owner, &m.neighbour})
    for (int64_t c : *list) last = std::max(last, c);
  m.cell_count = declared ? *declared : uint64_t(last + 1);
  const auto check = [&](Cursor& in, const std::vector<int64_t>& cells, const char* what) {
    for (size_t f = 0; f < cells.size(); ++f)
      if (cells[f] < 0 || uint64_t(cells[f]) >= m.cell_count)
        in.fail(std::string(what) + " of face " + std::to_string(f) + ": cell " + std::to_string(cells[f]) +
                " out of range 0.." + std::to_string(int64_t(m.cell_count) - 1));
  };
  check(owner, m.owner, "the owner");
  check(neighbour, m.neighbour, "the neighbour");
  if (m.cell_count == 0) owner.fail("no cells");
  // Each cell has 4 faces at least, each face 2 cells at most: a bound on what the cell count
  // (from the note) may make us allocate.
  if (m.cell_count > faces / 2 + 1)
    owner.fail(std::to_string(m.cell_count) + " cells of " + std::to_string(faces) + " faces");
}

PolyMesh read_poly_mesh(CaseFiles& files, const fs::path& dir) {
  PolyMesh m;
  m.points = read_points(files, dir);
  read_faces(files, dir, m);
  read_owners(files, dir, m);
  return m;
}

// A decomposed case (decomposePar's layout): processor0 .. processorN-1, each a case of its own
// cells, whose meshes are joined here as reconstructPar joins them.

// The case's processor directories in order (none where it has none): processor0 ..
// processorN-1, or for a collated case processors<N>/processor0 .. N-1 (on_disk). InputError for
// a gap in the numbers, a name with leading zeros (not OpenFOAM's), collated directories for
// two processor counts, or a collated one split over I/O ranks (processors<N>_<first>-<last>).
std::vector<fs::path> processor_directories(const fs::path& case_dir) {
  std::map<uint64_t, fs::path> by_number;
  std::vector<fs::path> collated;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(case_dir, ec)) {
    const std::string name = e.path().filename().string();
    if (!e.is_directory(ec) || !name.starts_with("processor")) continue;
    if (name.starts_with("processors")) {
      if (!number_after(name, "processors"))
        input_error(e.path().string(),
                    "a collated case split over I/O ranks (processors<N>_<first>-<last>): not read; reconstruct it "
                    "(reconstructParMesh, reconstructPar) or decompose it without ioRanks");
      collated.push_back(e.path());
      continue;
    }
    const std::optional<uint64_t> number = number_after(name, "processor");
    if (!number)
      input_error(e.path().string(),
                  "not a processor directory as decomposePar names them (processor0, processor1 ...)");
    by_number[*number] = e.path();
  }
  std::vector<fs::path> processors;
  for (const auto& [number, dir] : by_number) {
    if (number != processors.size())
      input_error((case_dir / ("processor" + std::to_string(processors.size()))).string(),
                  "missing, though processor" + std::to_string(number) +
                      " is there: a decomposed case is processor0 .. processorN-1, every one");
    processors.push_back(dir);
  }
  if (!processors.empty() || collated.empty()) return processors;
  std::sort(collated.begin(), collated.end());
  if (collated.size() > 1)
    input_error(collated[1].string(), "a second collated decomposition beside " + collated[0].filename().string() +
                                          ": remove the one not wanted");
  const uint64_t count = *number_after(collated[0].filename().string(), "processors");
  if (count == 0 || count > (uint64_t(1) << 24))
    input_error(collated[0].string(), "a collated decomposition into " + std::to_string(count) + " processors");
  for (uint64_t k = 0; k < count; ++k) processors.push_back(collated[0] / ("processor" + std::to_string(k)));
  return processors;
}

// A processor's pointProcAddressing: each of its `points` points' number in the whole mesh
// (decomposePar writes it, and reconstructPar joins the points through it).
std::vector<int64_t> read_point_addressing(CaseFiles& files, const fs::path& mesh_dir, uint64_t points) {
  if (!find_file(mesh_dir, "pointProcAddressing"))
    input_error((mesh_dir / "pointProcAddressing").string(),
                "missing: the processors' shared points are joined through it (decomposePar writes it; or join "
                "the case with reconstructPar, after reconstructParMesh where constant/polyMesh is gone)");
  Header h;
  Cursor in = open_mesh_file(files, mesh_dir, "pointProcAddressing", h);
  std::vector<int64_t> ids = read_label_list(in, h, "point numbers");
  if (ids.size() != points)
    in.fail(std::to_string(ids.size()) + " point numbers for the processor's " + std::to_string(points) + " points");
  for (size_t p = 0; p < ids.size(); ++p)
    if (ids[p] < 0) in.fail("point " + std::to_string(p) + ": a negative number " + std::to_string(ids[p]));
  return ids;
}

// A processor's points, kept until every processor is read: only then is the whole mesh's
// point count, which bounds their numbers, known.
struct ProcessorPoints {
  std::vector<vec3d> points;
  std::vector<int64_t> ids;  // pointProcAddressing
  fs::path file;             // pointProcAddressing's
};

std::string coordinates(const vec3d& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.17g %.17g %.17g)", p[0], p[1], p[2]);
  return text;
}

// decomposePar writes a shared point's coordinates bitwise alike in each processor; a relative
// 1e-9 allows for a writer that rounds them differently, not for another point.
bool same_point(const vec3d& a, const vec3d& b) {
  double scale = 0;
  for (int k = 0; k < 3; ++k) scale = std::max({scale, std::abs(a[k]), std::abs(b[k])});
  for (int k = 0; k < 3; ++k)
    if (!(std::abs(a[k] - b[k]) <= 1e-9 * scale)) return false;
  return true;
}

// The whole mesh's points: processor K's point p is point ids[p], and a point that several
// processors share is the same point in each. InputError for a number out of range, a point in
// no processor, or one whose processors disagree on where it is.
std::vector<vec3d> join_points(const std::vector<ProcessorPoints>& processors, const fs::path& pattern) {
  uint64_t bound = 0;  // the whole mesh has no more points than its processors together
  for (const ProcessorPoints& part : processors) bound += part.points.size();
  uint64_t count = 0;
  for (const ProcessorPoints& part : processors)
    for (size_t p = 0; p < part.ids.size(); ++p) {
      if (uint64_t(part.ids[p]) >= bound)
        input_error(part.file.string(), "point " + std::to_string(p) + ": number " + std::to_string(part.ids[p]) +
                                            " out of range 0.." + std::to_string(bound - 1) +
                                            " (the processors' points together)");
      count = std::max(count, uint64_t(part.ids[p]) + 1);
    }
  constexpr uint32_t kNone = ~uint32_t(0);
  std::vector<vec3d> points(count);
  std::vector<uint32_t> placed_by(count, kNone);  // the first processor that has the point
  for (uint32_t k = 0; k < processors.size(); ++k) {
    const ProcessorPoints& part = processors[k];
    for (size_t p = 0; p < part.ids.size(); ++p) {
      const uint64_t id = uint64_t(part.ids[p]);
      if (placed_by[id] == kNone) {
        placed_by[id] = k;
        points[id] = part.points[p];
      } else if (!same_point(points[id], part.points[p])) {
        input_error(part.file.string(), "point " + std::to_string(p) + " (point " + std::to_string(id) +
                                            " of the whole mesh) is at " + coordinates(part.points[p]) + ", but at " +
                                            coordinates(points[id]) + " in processor" + std::to_string(placed_by[id]));
      }
    }
  }
  const auto unplaced = std::find(placed_by.begin(), placed_by.end(), kNone);
  if (unplaced != placed_by.end())
    input_error((pattern / "pointProcAddressing").string(),
                "point " + std::to_string(unplaced - placed_by.begin()) + " of the whole mesh is in no processor");
  return points;
}

// A processor's mesh after those of the processors before it: its faces' vertices numbered as
// the whole mesh's points (`ids`), its cells after theirs. Its faces on the boundary between
// processors, which the processor on the other side has too (the other way round), have their
// owner alone, as its other boundary faces: each cell is built from its own processor's faces.
// (A part joined before, a region's processors, has neighbour -1 on its boundary faces.)
void append_processor(PolyMesh& whole, const PolyMesh& part, const std::vector<int64_t>& ids) {
  const uint64_t first_vertex = whole.face_vertices.size();
  const int64_t first_cell = int64_t(whole.cell_count);
  for (size_t f = 1; f < part.face_offsets.size(); ++f)
    whole.face_offsets.push_back(first_vertex + part.face_offsets[f]);
  for (uint64_t v : part.face_vertices) whole.face_vertices.push_back(saturated_face_index(ids[v]));
  for (int64_t c : part.owner) whole.owner.push_back(first_cell + c);
  for (size_t f = 0; f < part.owner.size(); ++f)
    whole.neighbour.push_back(f < part.neighbour.size() && part.neighbour[f] >= 0 ? first_cell + part.neighbour[f]
                                                                                  : -1);
  whole.cell_count += part.cell_count;
}

// The processors' meshes (`mesh_dirs`, one for each, in order) joined into one, their cells in
// processor order; `cells` gets each processor's cell count. `pattern` names the processors' mesh
// directories together in messages (case/processor*/constant/polyMesh).
PolyMesh read_decomposed_mesh(CaseFiles& files, const std::vector<fs::path>& mesh_dirs, const fs::path& pattern,
                              std::vector<uint64_t>& cells) {
  PolyMesh whole;
  std::vector<ProcessorPoints> points;
  for (const fs::path& mesh_dir : mesh_dirs) {
    PolyMesh part = read_poly_mesh(files, mesh_dir);
    std::vector<int64_t> ids = read_point_addressing(files, mesh_dir, part.points.size());
    append_processor(whole, part, ids);
    cells.push_back(part.cell_count);
    points.push_back({std::move(part.points), std::move(ids), *find_file(mesh_dir, "pointProcAddressing")});
  }
  whole.points = join_points(points, pattern);
  whole.owner_file = pattern / "owner";
  return whole;
}

// A region's mesh after those of the regions before it: regions share no points (each has its
// own copy of the points on the faces between them), so its points follow theirs.
void append_region(PolyMesh& whole, PolyMesh&& region) {
  if (whole.cell_count == 0 && whole.points.empty()) {
    whole = std::move(region);
    return;
  }
  whole.neighbour.resize(whole.owner.size(), -1);  // the boundary faces', past the internal ones
  std::vector<int64_t> ids(region.points.size());
  std::iota(ids.begin(), ids.end(), int64_t(whole.points.size()));
  append_processor(whole, region, ids);
  whole.points.insert(whole.points.end(), region.points.begin(), region.points.end());
}

// Each cell a polyhedron of the faces that name it (owner or neighbour), for split_polyhedra;
// the faces' vertices move there, and the owners and neighbours are dropped (nothing else needs
// them).
PolyhedronFaces cell_faces(PolyMesh& m) {
  std::vector<FaceCells> sides(m.owner.size());
  for (size_t f = 0; f < sides.size(); ++f)
    sides[f] = {uint64_t(m.owner[f]) + 1,
                f < m.neighbour.size() && m.neighbour[f] >= 0 ? uint64_t(m.neighbour[f]) + 1 : 0};
  release(m.owner);
  release(m.neighbour);
  return polyhedra_from_face_cells(std::move(m.face_offsets), std::move(m.face_vertices), sides, m.cell_count,
                                   m.owner_file.string());
}

bool is_time_name(const std::string& name, double& time) {
  const char* first = name.data();
  const auto [end, ec] = std::from_chars(first, name.data() + name.size(), time);
  return !name.empty() && ec == std::errc() && end == name.data() + name.size() && std::isfinite(time);
}

// A field file of a time directory, as its header tells.
struct FieldFile {
  std::string name;  // the file's, without .gz
  fs::path file;
  int components = 0;  // 1: volScalarField, 3: volVectorField; 0: skipped
  std::string class_name;
};

std::optional<FieldFile> field_file(const fs::path& file) {
  std::string name = file.filename().string();
  if (name.empty() || name.front() == '.' || name.back() == '~' || name.ends_with(".orig")) return std::nullopt;
  if (name_ends_with(file, ".gz")) name.erase(name.size() - 3);
  Cursor in(CaseFiles::start(file, 4096), file.string());
  in.skip_space_and_comments();
  if (!in.rest().starts_with("FoamFile")) return std::nullopt;  // not an OpenFOAM file
  Header h;
  try {
    h = in.header();
  } catch (const InputError&) {
    return std::nullopt;  // a header longer than we looked at, or damaged: not a field we read
  }
  FieldFile f{name, file, 0, h.class_name};
  if (h.class_name == "volScalarField") f.components = 1;
  if (h.class_name == "volVectorField") f.components = 3;
  return f;
}

// A volScalarField's or volVectorField's internalField, for `cells` cells.
std::vector<double> read_field(CaseFiles& files, const FieldFile& f, uint64_t cells) {
  Cursor in(files.read(f.file), f.file.string());
  const Header h = in.header();
  if (h.class_name != f.class_name) in.fail("class '" + h.class_name + "' changed while reading");
  for (;;) {
    const std::string_view key = in.token();
    if (key.empty()) in.fail("no internalField");
    if (key.front() == '#') {  // #include "file", #inputMode merge ...
      in.skip_line();
      continue;
    }
    if (key.size() == 1 && std::string_view("(){}[];").find(key) != std::string_view::npos)
      in.fail("unbalanced parentheses or braces ('" + std::string(key) + "' where an entry starts)");
    if (key != "internalField") {
      in.skip_entry();
      continue;
    }
    const std::string_view kind = in.token();
    std::vector<double> v;
    if (kind == "uniform") {
      double one[3] = {};
      if (f.components == 1) {
        one[0] = in.scalar("a uniform value");
      } else {
        in.expect('(', "opening a uniform vector");
        for (int k = 0; k < 3; ++k) one[k] = in.scalar("a uniform vector");
        in.expect(')', "closing a uniform vector");
      }
      v.resize(size_t(cells) * size_t(f.components));
      for (size_t i = 0; i < v.size(); ++i) v[i] = one[i % size_t(f.components)];
    } else if (kind == "nonuniform") {
      const std::string_view type = in.token();
      const char* expected = f.components == 1 ? "List<scalar>" : "List<vector>";
      if (type != expected) in.fail("internalField nonuniform " + std::string(type) + ", not " + expected);
      v = read_scalars(in, h, f.components, cells, "internalField values");
    } else {
      in.fail("internalField " + std::string(kind) + ": uniform or nonuniform expected");
    }
    in.expect(';', "after the internalField");
    return v;
  }
}

// The case directory an input names.
fs::path case_directory_of(const fs::path& input) {
  std::error_code ec;
  fs::path dir = input.parent_path();  // of a .foam file
  if (fs::is_directory(input, ec))
    dir = input;
  else if (input.filename() == "controlDict" && input.parent_path().filename() == "system")
    dir = input.parent_path().parent_path();
  return dir.empty() ? fs::path(".") : dir;  // "run.foam" in the working directory
}

}  // namespace

bool is_openfoam_input(const fs::path& input) {
  std::error_code ec;
  if (fs::is_directory(input, ec)) {
    if (fs::is_directory(input / "constant" / "polyMesh", ec) ||
        fs::is_regular_file(input / "system" / "controlDict", ec) || fs::is_directory(input / "processor0", ec))
      return true;
    for (const auto& e : fs::directory_iterator(input, ec))  // a collated case's processors<N>
      if (e.path().filename().string().starts_with("processors") && e.is_directory(ec)) return true;
    return false;
  }
  return name_ends_with(input, ".foam") || name_ends_with(input, ".openfoam") ||
         (input.filename() == "controlDict" && input.parent_path().filename() == "system");
}

namespace {

// OpenFOAM's name for the default region, whose mesh is constant/polyMesh (the solvers'
// -region option takes it).
constexpr const char* kDefaultRegion = "region0";

// `dir`, or its subdirectory for a region other than the default (constant/REGION, TIME/REGION).
fs::path in_region(const fs::path& dir, const std::string& region) {
  return region == kDefaultRegion ? dir : dir / region;
}

// The regions whose meshes `root` (a case or processor directory) holds: region0 where it has
// constant/polyMesh, then each directory of constant with a polyMesh, as splitMeshRegions writes
// a multi-region case's (chtMultiRegionFoam's), by name.
std::vector<std::string> regions_in(const fs::path& root) {
  std::error_code ec;
  std::vector<std::string> names;
  const fs::path constant = on_disk(root / "constant").path;
  for (const auto& e : fs::directory_iterator(constant, ec))
    if (e.is_directory(ec) && e.path().filename() != "polyMesh" && fs::is_directory(e.path() / "polyMesh", ec))
      names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  if (fs::is_directory(constant / "polyMesh", ec)) names.insert(names.begin(), kDefaultRegion);
  return names;
}

}  // namespace

struct OpenFoamCase::Impl {
  fs::path dir;
  // Where the meshes and the time steps are: the case directory, or a decomposed case's
  // processor directories, whose cells follow one another in each region, processor0's first.
  std::vector<fs::path> roots;
  CaseFiles case_files;
  struct Region {
    std::string name;                  // region0: constant/polyMesh
    std::vector<uint64_t> root_cells;  // the cells in each root
    uint64_t cells = 0;
  };
  std::vector<Region> regions;       // those read, their cells one after another in the mesh
  bool default_region_left = false;  // constant/polyMesh not read beside the regions
  PolyMesh mesh;
  PolyhedronFaces faces;  // released once split
  uint64_t face_count = 0;
  std::optional<FixedMeshSplit> split;  // made at the first step read
  // A field of a step, and the regions that have it (NaN, no data, in the others).
  struct StepField {
    std::string name, class_name;
    int components = 0;
    std::vector<char> in_region;
  };
  struct Step {
    double time = 0;
    fs::path dir;  // the first root's time directory
    std::vector<StepField> fields;
  };
  std::vector<Step> steps;
  std::set<std::string> left_out, skipped, no_data;

  // The case's own meshes, or its processors' joined. Where it has both, as a case run in
  // parallel from a mesh made whole has (blockMesh, decomposePar, the solver), the processors
  // are read when their last time is later than the case's own: the results are there.
  void read_mesh(const std::vector<std::string>& wanted) {
    const std::vector<fs::path> processors = processor_directories(dir);
    if (!regions_in(dir).empty() && (processors.empty() || last_time(processors.front()) <= last_time(dir))) {
      roots = {dir};
    } else if (!processors.empty()) {
      roots = processors;
    } else {
      input_error((dir / "constant" / "polyMesh").string(),
                  "missing: not an OpenFOAM case (no constant/polyMesh, nor a region's constant/REGION/polyMesh)");
    }
    choose_regions(wanted);
    for (Region& r : regions) append_region(mesh, read_region_mesh(r));
    if (regions.size() > 1) {
      std::vector<std::string> names;
      for (const Region& r : regions) names.push_back(r.name);
      mesh.owner_file = root_pattern() / "constant" / ("{" + joined(names, ",") + "}") / "polyMesh" / "owner";
    }
  }

  // The regions read: those `wanted` (InputError naming the case's for one it lacks), else the
  // named regions of a multi-region case (its constant/polyMesh, if still there, is the mesh
  // before splitMeshRegions cut it up; no solver reads it), else region0.
  void choose_regions(const std::vector<std::string>& wanted) {
    const std::vector<std::string> found = regions_in(roots.front());
    std::vector<std::string> names;
    for (const std::string& w : wanted) {
      if (std::find(found.begin(), found.end(), w) == found.end())
        input_error(in_region(roots.front() / "constant", w).string(),
                    "no region '" + w + "' in this case (its regions: " + joined(found) + ")");
      if (std::find(names.begin(), names.end(), w) == names.end()) names.push_back(w);
    }
    if (names.empty()) {
      names = found.empty() ? std::vector<std::string>{kDefaultRegion} : found;  // none: "polyMesh/points: missing"
      if (names.size() > 1 && names.front() == kDefaultRegion) {
        names.erase(names.begin());
        default_region_left = true;
      }
    }
    for (const std::string& n : names) regions.push_back({n, {}, 0});
  }

  // The roots in messages: the case, or case/processor* (case/processors<N>/processor* collated).
  fs::path root_pattern() const { return roots.front() == dir ? dir : roots.front().parent_path() / "processor*"; }

  PolyMesh read_region_mesh(Region& r) {
    PolyMesh m;
    if (roots.front() == dir) {
      m = read_poly_mesh(case_files, in_region(dir / "constant", r.name) / "polyMesh");
      r.root_cells = {m.cell_count};
    } else {
      std::vector<fs::path> mesh_dirs;
      for (const fs::path& root : roots) mesh_dirs.push_back(in_region(root / "constant", r.name) / "polyMesh");
      m = read_decomposed_mesh(case_files, mesh_dirs, in_region(root_pattern() / "constant", r.name) / "polyMesh",
                               r.root_cells);
      case_files.forget();
    }
    r.cells = m.cell_count;
    return m;
  }

  // The latest time directory's value in `d` (-infinity where it has none).
  static double last_time(const fs::path& d) {
    std::error_code ec;
    double last = -INFINITY, t = 0;
    for (const auto& e : fs::directory_iterator(on_disk(d).path, ec))
      if (e.is_directory(ec) && is_time_name(e.path().filename().string(), t)) last = std::max(last, t);
    return last;
  }

  // The file of a step's field in region `r` of root `k`.
  FieldFile field_file_in(const Step& step, const StepField& f, size_t r, size_t k) const {
    const fs::path time_dir = in_region(roots[k] / step.dir.filename(), regions[r].name);
    const std::optional<fs::path> file = find_file(time_dir, f.name);
    if (!file) input_error((time_dir / f.name).string(), k == 0 ? "missing" : "missing (processor0 has it)");
    return {f.name, *file, f.components, f.class_name};
  }

  // The volScalarField and volVectorField files of a time directory, by name (other fields
  // noted as skipped).
  std::map<std::string, FieldFile> fields_in(const fs::path& time_dir) {
    std::error_code ec;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(on_disk(time_dir).path, ec))
      if (e.is_regular_file(ec)) files.push_back(time_dir / e.path().filename());
    std::sort(files.begin(), files.end());
    std::map<std::string, FieldFile> fields;
    for (const fs::path& file : files) {
      const std::optional<FieldFile> f = field_file(file);
      if (!f) continue;
      if (f->components == 0)
        skipped.insert(f->name + " (" + f->class_name + ")");
      else
        fields.try_emplace(f->name, *f);
    }
    return fields;
  }

  // A region's fields in a time directory of the first root that every root has; those that
  // some root lacks are left out. InputError for a root without the time directory.
  void keep_fields_in_every_root(const std::string& time_name, const std::string& region,
                                 std::map<std::string, FieldFile>& fields) {
    std::error_code ec;
    for (size_t k = 1; k < roots.size(); ++k) {
      const fs::path other = in_region(roots[k] / time_name, region);
      if (!fs::is_directory(on_disk(other).path, ec))
        input_error(other.string(),
                    "missing, though processor0 has time " + time_name + ": every processor must have every time step");
      for (auto it = fields.begin(); it != fields.end();)
        if (find_file(other, it->first)) {
          ++it;
        } else {
          left_out.insert(it->first);
          it = fields.erase(it);
        }
    }
  }

  // The fields of one time directory, in any region.
  std::map<std::string, StepField> step_fields(const fs::path& time_dir) {
    std::map<std::string, StepField> fields;
    for (size_t r = 0; r < regions.size(); ++r) {
      const fs::path region_dir = in_region(time_dir, regions[r].name);
      if (find_file(region_dir / "polyMesh", "points") || find_file(region_dir / "polyMesh", "faces"))
        input_error((region_dir / "polyMesh").string(),
                    "a moving or changing mesh (a polyMesh in a time directory): not read; foamToVTK writes each "
                    "step's mesh");
      std::map<std::string, FieldFile> found = fields_in(region_dir);
      if (found.empty()) continue;
      keep_fields_in_every_root(time_dir.filename().string(), regions[r].name, found);
      for (const auto& [name, f] : found) {
        StepField& s =
            fields.try_emplace(name, StepField{name, f.class_name, f.components, std::vector<char>(regions.size(), 0)})
                .first->second;
        if (s.components == f.components)
          s.in_region[r] = 1;
        else
          skipped.insert(name + " in region " + regions[r].name + " (" + f.class_name + ", but " + s.class_name +
                         " in another)");
      }
    }
    return fields;
  }

  void find_steps() {
    std::error_code ec;
    std::vector<std::pair<double, fs::path>> times;
    for (const auto& e : fs::directory_iterator(on_disk(roots.front()).path, ec)) {
      double t = 0;
      const fs::path name = e.path().filename();
      if (e.is_directory(ec) && is_time_name(name.string(), t)) times.push_back({t, roots.front() / name});
    }
    std::sort(times.begin(), times.end());
    std::vector<std::map<std::string, StepField>> found;
    for (const auto& [t, time_dir] : times) {
      std::map<std::string, StepField> fields = step_fields(time_dir);
      if (fields.empty()) continue;
      steps.push_back({t, time_dir, {}});
      found.push_back(std::move(fields));
    }
    // Those in every step (of the same class) are read; the others are left out. A region
    // without a field has no data (NaN) there.
    for (size_t s = 0; s < steps.size(); ++s)
      for (const auto& entry : found[s]) {
        const std::string& name = entry.first;  // not bindings: clang 14's lambdas cannot capture them
        const StepField& f = entry.second;
        const bool everywhere = std::all_of(found.begin(), found.end(), [&](const auto& other) {
          const auto it = other.find(name);
          return it != other.end() && it->second.components == f.components;
        });
        if (!everywhere) {
          left_out.insert(name);
          continue;
        }
        steps[s].fields.push_back(f);
        for (size_t r = 0; r < regions.size(); ++r)
          if (!f.in_region[r]) no_data.insert(name + " in " + regions[r].name);
      }
    if (steps.empty())
      steps.push_back({0.0, in_region(roots.front() / "constant", regions.front().name) / "polyMesh", {}});
  }
};

OpenFoamCase::OpenFoamCase(const fs::path& input, const std::vector<std::string>& regions)
    : impl_(std::make_unique<Impl>()) {
  Impl& c = *impl_;
  c.dir = case_directory_of(input);
  c.read_mesh(regions);
  c.faces = cell_faces(c.mesh);
  c.face_count = c.faces.face_offsets.size() - 1;
  c.find_steps();
}
OpenFoamCase::~OpenFoamCase() = default;

size_t OpenFoamCase::step_count() const { return impl_->steps.size(); }
double OpenFoamCase::step_time(size_t step) const { return impl_->steps.at(step).time; }
fs::path OpenFoamCase::step_file(size_t step) const { return impl_->steps.at(step).dir; }
fs::path OpenFoamCase::case_directory() const { return impl_->dir; }

FixedMeshSplit& OpenFoamCase::split_mesh() {
  Impl& c = *impl_;
  if (!c.split) {
    MeshData m;
    m.points = std::move(c.mesh.points);  // the split keeps them
    m.cell_types.assign(c.mesh.cell_count, kVtkPolyhedron);
    m.cell_offsets.assign(c.mesh.cell_count + 1, 0);  // a polyhedron's vertices are its faces'
    c.split.emplace(std::move(m), c.faces, c.mesh.owner_file.string());
    c.faces = {};
  }
  return *c.split;
}

std::vector<MeshArray> OpenFoamCase::read_cell_data(size_t step) {
  Impl& c = *impl_;
  input_check(step < step_count(), c.dir.string(), "no time step " + std::to_string(step));
  const Impl::Step& s = c.steps[step];
  std::vector<MeshArray> cell_data;
  for (const Impl::StepField& f : s.fields) {
    MeshArray& a = cell_data.emplace_back(MeshArray{f.name, f.components, {}});
    for (size_t r = 0; r < c.regions.size(); ++r) {
      const Impl::Region& region = c.regions[r];
      if (!f.in_region[r]) {
        a.values.insert(a.values.end(), region.cells * uint64_t(f.components), std::nan(""));
        continue;
      }
      for (size_t k = 0; k < c.roots.size(); ++k) {
        std::vector<double> values = read_field(c.case_files, c.field_file_in(s, f, r, k), region.root_cells[k]);
        if (a.values.empty())
          a.values = std::move(values);
        else
          a.values.insert(a.values.end(), values.begin(), values.end());
      }
      c.case_files.forget();
    }
  }
  split_mesh().split_cell_data(cell_data, s.dir.string());
  return cell_data;
}

MeshData OpenFoamCase::read_step(size_t step) {
  std::vector<MeshArray> cell_data = read_cell_data(step);
  return split_mesh().mesh_with(std::move(cell_data), impl_->steps[step].dir.string());
}

MeshData OpenFoamCase::take_step(size_t step) {
  std::vector<MeshArray> cell_data = read_cell_data(step);
  return split_mesh().take_mesh_with(std::move(cell_data), impl_->steps[step].dir.string());
}

std::string OpenFoamCase::summary() const {
  const Impl& c = *impl_;
  std::string s = std::to_string(c.mesh.cell_count) + " cells, " + std::to_string(c.face_count) + " faces";
  if (c.roots.front() != c.dir)  // decomposed
    s += ", decomposed into " + std::to_string(c.roots.size()) + (c.roots.size() == 1 ? " processor" : " processors") +
         " (the faces between them counted in each)";
  if (c.regions.size() > 1 || c.regions.front().name != kDefaultRegion) {
    std::vector<std::string> regions;
    for (const Impl::Region& r : c.regions) regions.push_back(r.name + " " + std::to_string(r.cells));
    s += "; regions (cells) " + joined(regions);
  }
  if (c.default_region_left) s += " (not constant/polyMesh: --region region0 reads it)";
  std::vector<std::string> fields;
  for (const Impl::StepField& f : c.steps.front().fields) fields.push_back(f.name);
  if (!fields.empty()) s += "; fields " + joined(fields);
  const auto list = [&](const char* title, const std::set<std::string>& names) {
    if (!names.empty()) s += title + joined(std::vector<std::string>(names.begin(), names.end()));
  };
  list("; no data (NaN) for ", c.no_data);
  list("; left out (not in every time step): ", c.left_out);
  list("; skipped: ", c.skipped);
  return s;
}

}  // namespace vs
