#include "volstream/io/openfoam.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <string_view>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/byte_order.h"
#include "volstream/io/parse_cursor.h"
#include "volstream/umesh/polyhedra.h"

namespace vs {
namespace fs = std::filesystem;

namespace {

// `dir/name`, or `dir/name.gz` where only that exists (writeCompression on); nullopt for neither.
std::optional<fs::path> find_file(const fs::path& dir, const std::string& name) {
  std::error_code ec;
  for (const std::string& n : {name, name + ".gz"})
    if (fs::is_regular_file(dir / n, ec)) return dir / n;
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

// A list of labels, "N ( a b ... )" or "N { a }" (uniform), ascii or binary as `h` says.
std::vector<int64_t> read_labels(Cursor& in, const Header& h, const char* what) {
  const int64_t n = in.label(what);
  if (n < 0) in.fail(std::string("a negative count of ") + what);
  if (in.peek('{')) {
    in.seek(in.position() + 1);
    in.require_fits(uint64_t(n) / 64, 1, what);  // a uniform list of labels, in a mesh file, is short
    const int64_t v = in.label(what);
    in.expect('}', "closing a uniform list");
    return std::vector<int64_t>(size_t(n), v);
  }
  in.expect('(', "opening a list");
  std::vector<int64_t> v;
  if (h.binary) {
    in.require_fits(uint64_t(n), uint64_t(h.label_bytes), what);
    v.resize(size_t(n));
    for (int64_t& x : v)
      x = h.label_bytes == 4 ? int64_t(in.binary<int32_t>(h.big_endian, what)) : in.binary<int64_t>(h.big_endian, what);
  } else {
    in.require_fits(uint64_t(n), 2, what);
    v.resize(size_t(n));
    for (int64_t& x : v) x = in.label(what);
  }
  in.expect(')', "closing a list");
  return v;
}

double binary_scalar(Cursor& in, const Header& h, const char* what) {
  return h.scalar_bytes == 4 ? double(in.binary<float>(h.big_endian, what)) : in.binary<double>(h.big_endian, what);
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
    for (double& x : v) x = binary_scalar(in, h, what);
  } else {
    in.require_fits(uint64_t(n), components == 1 ? 2 : 7, what);
    v.resize(size_t(n) * size_t(components));
    for (int64_t i = 0; i < n; ++i) item(&v[size_t(i) * size_t(components)]);
  }
  in.expect(')', "closing a list");
  return v;
}

// The mesh of constant/polyMesh.
struct PolyMesh {
  std::vector<vec3d> points;
  std::vector<uint64_t> face_offsets{0}, face_vertices;  // moved to the PolyhedronFaces once read
  std::vector<int64_t> owner, neighbour;                 // dropped once the cells' faces are built
  uint64_t cell_count = 0;
  fs::path owner_file;
};

Cursor open_mesh_file(const fs::path& dir, const char* name, Header& h) {
  const std::optional<fs::path> file = find_file(dir, name);
  if (!file) input_error((dir / name).string(), "missing: an OpenFOAM mesh is points, faces, owner and neighbour");
  Cursor in(read_file_inflating(*file), file->string());
  h = in.header();
  return in;
}
void expect_end(Cursor& in) {
  if (!in.at_end()) in.fail("more after the list");
}

std::vector<vec3d> read_points(const fs::path& dir) {
  Header h;
  Cursor in = open_mesh_file(dir, "points", h);
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
void add_vertex(Cursor& in, PolyMesh& m, uint64_t face, int64_t v) {
  if (v < 0 || uint64_t(v) >= m.points.size())
    in.fail("face " + std::to_string(face) + ": point " + std::to_string(v) + " out of range 0.." +
            std::to_string(m.points.size() - 1));
  m.face_vertices.push_back(uint64_t(v));
}

// faceCompactList: the offsets (faces + 1), then every face's vertices; faceList: "N ( n(a b c)
// ... )", each face a list of its own (in binary files too).
void read_faces(const fs::path& dir, PolyMesh& m) {
  Header h;
  Cursor in = open_mesh_file(dir, "faces", h);
  if (h.class_name == "faceCompactList") {
    const std::vector<int64_t> offsets = read_labels(in, h, "face offsets");
    const std::vector<int64_t> vertices = read_labels(in, h, "face vertices");
    expect_end(in);
    if (offsets.empty() || offsets.front() != 0 || uint64_t(offsets.back()) != vertices.size())
      in.fail("the face offsets do not span the " + std::to_string(vertices.size()) + " face vertices");
    m.face_vertices.reserve(vertices.size());
    m.face_offsets.reserve(offsets.size());
    for (size_t f = 0; f + 1 < offsets.size(); ++f) {
      if (offsets[f + 1] < offsets[f]) in.fail("the face offsets decrease at face " + std::to_string(f));
      add_face(in, m, f, uint64_t(offsets[f + 1] - offsets[f]));
    }
    for (size_t f = 0; f + 1 < offsets.size(); ++f)
      for (int64_t k = offsets[f]; k < offsets[f + 1]; ++k) add_vertex(in, m, f, vertices[size_t(k)]);
    return;
  }
  if (h.class_name != "faceList") in.fail("class '" + h.class_name + "', not faceList or faceCompactList");
  const int64_t n = in.label("the face count");
  if (n < 0) in.fail("a negative face count");
  in.expect('(', "opening the faces");
  in.require_fits(uint64_t(n), h.binary ? 3 * uint64_t(h.label_bytes) : 8, "faces");
  m.face_offsets.reserve(size_t(n) + 1);
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

void read_owners(const fs::path& dir, PolyMesh& m) {
  const uint64_t faces = m.face_offsets.size() - 1;
  Header h;
  Cursor owner = open_mesh_file(dir, "owner", h);
  if (h.class_name != "labelList") owner.fail("class '" + h.class_name + "', not labelList");
  m.owner = read_labels(owner, h, "owners");
  expect_end(owner);
  m.owner_file = owner.file();
  if (m.owner.size() != faces)
    owner.fail(std::to_string(m.owner.size()) + " owners of " + std::to_string(faces) + " faces");
  const std::optional<uint64_t> declared = note_count(h.note, "nCells");

  Header hn;
  Cursor neighbour = open_mesh_file(dir, "neighbour", hn);
  if (hn.class_name != "labelList") neighbour.fail("class '" + hn.class_name + "', not labelList");
  m.neighbour = read_labels(neighbour, hn, "neighbours");
  expect_end(neighbour);
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

PolyMesh read_poly_mesh(const fs::path& dir) {
  PolyMesh m;
  m.points = read_points(dir);
  read_faces(dir, m);
  read_owners(dir, m);
  return m;
}

// Each cell a polyhedron of the faces that name it (owner or neighbour), for split_polyhedra;
// the faces' vertices move there, and the owners and neighbours are dropped (nothing else needs
// them).
PolyhedronFaces cell_faces(PolyMesh& m) {
  std::vector<FaceCells> sides(m.owner.size());
  for (size_t f = 0; f < sides.size(); ++f)
    sides[f] = {uint64_t(m.owner[f]) + 1, f < m.neighbour.size() ? uint64_t(m.neighbour[f]) + 1 : 0};
  m.owner = {};
  m.neighbour = {};
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
  Cursor in(read_file_inflating(file, 4096), file.string());
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
std::vector<double> read_field(const FieldFile& f, uint64_t cells) {
  Cursor in(read_file_inflating(f.file), f.file.string());
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
  if (fs::is_directory(input, ec))
    return fs::is_directory(input / "constant" / "polyMesh", ec) ||
           fs::is_regular_file(input / "system" / "controlDict", ec) || fs::is_directory(input / "processor0", ec);
  return name_ends_with(input, ".foam") || name_ends_with(input, ".openfoam") ||
         (input.filename() == "controlDict" && input.parent_path().filename() == "system");
}

struct OpenFoamCase::Impl {
  fs::path dir, mesh_dir;
  PolyMesh mesh;
  PolyhedronFaces faces;  // released once split
  uint64_t face_count = 0;
  std::optional<FixedMeshSplit> split;  // made at the first step read
  struct Step {
    double time = 0;
    fs::path dir;
    std::vector<FieldFile> fields;  // those read
  };
  std::vector<Step> steps;
  std::set<std::string> left_out, skipped;

  void find_steps() {
    std::error_code ec;
    std::vector<std::pair<double, fs::path>> times;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
      double t = 0;
      if (e.is_directory(ec) && is_time_name(e.path().filename().string(), t)) times.push_back({t, e.path()});
    }
    std::sort(times.begin(), times.end());
    std::vector<std::map<std::string, FieldFile>> found;
    for (const auto& [t, tdir] : times) {
      if (find_file(tdir / "polyMesh", "points") || find_file(tdir / "polyMesh", "faces"))
        input_error((tdir / "polyMesh").string(),
                    "a moving or changing mesh (a polyMesh in a time directory): not read; foamToVTK writes each "
                    "step's mesh");
      std::map<std::string, FieldFile> fields;
      std::vector<fs::path> files;
      for (const auto& e : fs::directory_iterator(tdir, ec))
        if (e.is_regular_file(ec)) files.push_back(e.path());
      std::sort(files.begin(), files.end());
      for (const fs::path& file : files) {
        const std::optional<FieldFile> f = field_file(file);
        if (!f) continue;
        if (f->components == 0) {
          skipped.insert(f->name + " (" + f->class_name + ")");
          continue;
        }
        if (!fields.count(f->name)) fields[f->name] = *f;
      }
      if (fields.empty()) continue;
      steps.push_back({t, tdir, {}});
      found.push_back(std::move(fields));
    }
    // Those in every step (of the same class) are read; the others are left out.
    for (size_t s = 0; s < steps.size(); ++s)
      for (const auto& entry : found[s]) {
        const std::string& name = entry.first;
        const FieldFile& f = entry.second;
        const bool everywhere = std::all_of(found.begin(), found.end(), [&](const auto& other) {
          const auto it = other.find(name);
          return it != other.end() && it->second.components == f.components;
        });
        if (everywhere)
          steps[s].fields.push_back(f);
        else
          left_out.insert(name);
      }
    if (steps.empty()) steps.push_back({0.0, mesh_dir, {}});
  }
};

OpenFoamCase::OpenFoamCase(const fs::path& input) : impl_(std::make_unique<Impl>()) {
  Impl& c = *impl_;
  c.dir = case_directory_of(input);
  c.mesh_dir = c.dir / "constant" / "polyMesh";
  std::error_code ec;
  if (!fs::is_directory(c.mesh_dir, ec)) {
    if (fs::is_directory(c.dir / "processor0", ec))
      input_error(c.dir.string(),
                  "a decomposed case (processor0 ... without constant/polyMesh): run reconstructPar "
                  "(or reconstructParMesh) first");
    input_error(c.mesh_dir.string(), "missing: not an OpenFOAM case (no constant/polyMesh)");
  }
  c.mesh = read_poly_mesh(c.mesh_dir);
  c.faces = cell_faces(c.mesh);
  c.face_count = c.faces.face_offsets.size() - 1;
  c.find_steps();
}
OpenFoamCase::~OpenFoamCase() = default;

size_t OpenFoamCase::step_count() const { return impl_->steps.size(); }
double OpenFoamCase::step_time(size_t step) const { return impl_->steps.at(step).time; }
fs::path OpenFoamCase::step_file(size_t step) const { return impl_->steps.at(step).dir; }
fs::path OpenFoamCase::case_directory() const { return impl_->dir; }

const FixedMeshSplit& OpenFoamCase::split_mesh() {
  Impl& c = *impl_;
  if (!c.split) {
    MeshData m;
    m.points = c.mesh.points;
    m.cell_types.assign(c.mesh.cell_count, kVtkPolyhedron);
    m.cell_offsets.assign(c.mesh.cell_count + 1, 0);  // a polyhedron's vertices are its faces'
    c.split.emplace(std::move(m), c.faces, c.mesh.owner_file.string());
    c.faces = {};
  }
  return *c.split;
}

std::vector<MeshArray> OpenFoamCase::read_cell_data(size_t step) {
  const Impl& c = *impl_;
  input_check(step < step_count(), c.dir.string(), "no time step " + std::to_string(step));
  std::vector<MeshArray> cell_data, no_point_data;
  for (const FieldFile& f : c.steps[step].fields)
    cell_data.push_back({f.name, f.components, read_field(f, c.mesh.cell_count)});
  split_mesh().split_data(no_point_data, cell_data, c.steps[step].dir.string());
  return cell_data;
}

MeshData OpenFoamCase::read_step(size_t step) {
  std::vector<MeshArray> cell_data = read_cell_data(step);
  MeshData m = split_mesh().mesh();
  m.cell_data = std::move(cell_data);
  check_mesh(m, impl_->steps[step].dir.string());
  return m;
}

std::string OpenFoamCase::summary() const {
  const Impl& c = *impl_;
  std::string s = std::to_string(c.mesh.cell_count) + " cells, " + std::to_string(c.face_count) + " faces";
  const char* sep = "; fields ";
  for (const FieldFile& f : c.steps.front().fields) {
    s += sep + f.name;
    sep = ", ";
  }
  if (!c.left_out.empty()) {
    s += "; left out (not in every time step): ";
    for (const std::string& name : c.left_out) s += (name == *c.left_out.begin() ? "" : ", ") + name;
  }
  if (!c.skipped.empty()) {
    s += "; skipped: ";
    for (const std::string& name : c.skipped) s += (name == *c.skipped.begin() ? "" : ", ") + name;
  }
  return s;
}

}  // namespace vs
