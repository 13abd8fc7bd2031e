#include "volstream/io/ensight.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"
#include "volstream/io/parse_cursor.h"
#include "volstream/umesh/mesh_pieces.h"
#include "volstream/umesh/quadratic.h"

namespace vs {
namespace fs = std::filesystem;

namespace {

std::string str(uint64_t v) { return std::to_string(v); }

std::string trimmed(std::string_view s) {
  if (const size_t nul = s.find('\0'); nul != std::string_view::npos) s = s.substr(0, nul);
  while (!s.empty() && (std::isspace(static_cast<unsigned char>(s.back())) || s.back() == '\0')) s.remove_suffix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  return std::string(s);
}

std::string lower_trimmed(std::string_view s) { return lower_case(trimmed(s)); }

// ---------------------------------------------------------------------------------------------
// The case file.

std::vector<std::string> words_of(std::string_view text) {
  std::istringstream in{std::string(text)};
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

bool is_integer(const std::string& w) {
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
  return ec == std::errc() && end == w.data() + w.size();
}

// The words of a case file's sections, by "SECTION" and "key", each key's value the rest of its line
// and the lines after it that hold no ':' (a list of time values may span lines).
struct CaseEntry {
  std::string section, key;
  std::vector<std::string> value;
};

std::vector<CaseEntry> case_entries(const std::string& text) {
  std::vector<CaseEntry> entries;
  std::string section;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    const std::string trimmed = lower_trimmed(line);
    if (trimmed.empty()) continue;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) {
      const std::vector<std::string> words = words_of(line);
      const auto section_name = [](char c) { return std::isupper(static_cast<unsigned char>(c)) || c == '_'; };
      if (words.size() == 1 && std::all_of(words[0].begin(), words[0].end(), section_name)) {
        section = words[0];
      } else if (!entries.empty()) {
        entries.back().value.insert(entries.back().value.end(), words.begin(), words.end());
      }
      continue;
    }
    entries.push_back({section, lower_trimmed(line.substr(0, colon)), words_of(line.substr(colon + 1))});
  }
  return entries;
}

// "[ts] [fs] description file" (a variable) or "[ts] [fs] file" (the model): the file name, the
// description (variables) and the time set, or -1 for none given.
struct CaseFileRef {
  std::string description, file;
  int64_t time_set = -1;
};

CaseFileRef file_ref(const std::vector<std::string>& words, bool has_description, const std::string& origin) {
  const size_t named = has_description ? 2 : 1;
  if (words.size() < named || words.size() > named + 2)
    input_error(origin, "cannot read the entry '" + (words.empty() ? std::string() : words[0]) + " ...'");
  CaseFileRef ref;
  ref.file = words.back();
  if (has_description) ref.description = words[words.size() - 2];
  if (words.size() > named) {
    if (!is_integer(words[0])) input_error(origin, "'" + words[0] + "' is not a time set number");
    ref.time_set = std::stoll(words[0]);
  }
  return ref;
}

std::vector<double> numbers(const CaseEntry& e, const std::string& origin) {
  std::vector<double> out;
  for (const std::string& w : e.value) {
    double v = 0;
    const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
    if (ec != std::errc() || end != w.data() + w.size() || !std::isfinite(v))
      input_error(origin, e.key + ": '" + w + "' is not a number");
    out.push_back(v);
  }
  return out;
}

int64_t one_integer(const CaseEntry& e, const std::string& origin) {
  if (e.value.size() != 1 || !is_integer(e.value[0])) input_error(origin, e.key + ": expected one integer");
  return std::stoll(e.value[0]);
}

void read_time_section(const std::vector<CaseEntry>& entries, EnsightCase& c, const std::string& origin) {
  int64_t steps = -1, start = 0, increment = 1;
  std::vector<double> times, file_numbers;
  int sets = 0;
  for (const CaseEntry& e : entries) {
    if (e.section != "TIME") continue;
    if (e.key == "time set")
      ++sets;
    else if (e.key == "number of steps")
      steps = one_integer(e, origin);
    else if (e.key == "filename start number")
      start = one_integer(e, origin);
    else if (e.key == "filename increment")
      increment = one_integer(e, origin);
    else if (e.key == "time values")
      times = numbers(e, origin);
    else if (e.key == "filename numbers")
      file_numbers = numbers(e, origin);
  }
  if (sets == 0) return;
  input_check(sets == 1, origin, "several time sets (volstream reads cases of one)");
  input_check(steps >= 1 && steps <= (int64_t(1) << 24), origin, "number of steps is missing or out of range");
  input_check(times.size() == uint64_t(steps), origin,
              "time values: " + str(times.size()) + " values for " + str(uint64_t(steps)) + " steps");
  for (size_t i = 1; i < times.size(); ++i)
    input_check(times[i] > times[i - 1], origin, "time values: they must increase");
  c.times = times;
  if (!file_numbers.empty() && file_numbers.size() != uint64_t(steps))
    input_error(origin,
                "filename numbers: " + str(file_numbers.size()) + " values for " + str(uint64_t(steps)) + " steps");
  // Bounded so that no file number overflows (2^24 steps at most).
  constexpr int64_t kLargest = 1000000000000, kLargestIncrement = 1000000;
  input_check(
      start >= -kLargest && start <= kLargest && increment >= -kLargestIncrement && increment <= kLargestIncrement,
      origin, "filename start number or increment out of range");
  c.file_numbers.clear();
  for (int64_t i = 0; i < steps; ++i) {
    if (file_numbers.empty()) {
      c.file_numbers.push_back(start + i * increment);
      continue;
    }
    const double n = file_numbers[size_t(i)];
    input_check(n == std::floor(n) && std::fabs(n) <= double(kLargest), origin,
                "filename numbers: not integers in range");
    c.file_numbers.push_back(int64_t(n));
  }
}

// Variables volstream has no use for: constants, tensors, complex values, measured (particle) data.
bool skipped_variable_kind(const std::string& key) {
  return key.starts_with("constant per case") || key.starts_with("tensor") || key.starts_with("complex") ||
         key.find("per measured node") != std::string::npos;
}

EnsightCase::Variable variable_of(const CaseEntry& e, const std::string& origin) {
  EnsightCase::Variable v;
  const std::string& k = e.key;
  if (k != "scalar per node" && k != "vector per node" && k != "scalar per element" && k != "vector per element")
    input_error(origin,
                "unsupported variable kind '" + k + "' (volstream reads scalars and vectors per node or per element)");
  v.per_element = k.ends_with("element");
  v.components = k.starts_with("vector") ? 3 : 1;
  const CaseFileRef ref = file_ref(e.value, true, origin);
  v.name = ref.description;
  v.file = ref.file;
  return v;
}

// ---------------------------------------------------------------------------------------------
// Geometry and variable files: keywords, integers and floats, binary or ASCII alike.

class EnsightFile {
 public:
  EnsightFile(const fs::path& path, bool binary, bool big_endian) : in_(path), binary_(binary), big_(big_endian) {}
  const std::string& name() const { return in_.file(); }
  bool at_end() {
    if (binary_) return in_.remaining() == 0;
    const uint64_t at = in_.position();
    const bool end = !in_.try_word();
    in_.seek(at);
    return end;
  }
  // An 80-character line (binary) or a text line, lower case, trimmed; blank lines before it
  // are skipped.
  std::string keyword() {
    if (binary_) return lower_trimmed(std::string_view(in_.take(80, "an 80-character line"), 80));
    while (in_.remaining() && in_.at_blank_line()) in_.skip_line();
    if (!in_.remaining()) in_.fail("unexpected end of file, expected a keyword line");
    mid_line_ = false;
    return lower_trimmed(in_.line());
  }
  // A description line, which may be blank; trimmed.
  std::string description() {
    if (binary_) return trimmed(std::string_view(in_.take(80, "an 80-character line"), 80));
    if (mid_line_) in_.skip_line();  // the end of the line of the last number
    mid_line_ = false;
    if (!in_.remaining()) in_.fail("unexpected end of file, expected a description line");
    return trimmed(in_.line());
  }
  std::string peek_keyword() {
    const uint64_t at = in_.position();
    std::string k = keyword();
    in_.seek(at);
    return k;
  }
  int64_t integer(const char* what) {
    mid_line_ = !binary_;
    return binary_ ? int64_t(in_.binary<int32_t>(big_, what)) : in_.integer(what);
  }
  // A count of items of `values_each` values, which must fit in the rest of the file.
  uint64_t count(const char* what, uint64_t values_each) {
    const int64_t n = integer(what);
    if (n < 0) in_.fail(std::string(what) + ": negative count " + std::to_string(n));
    in_.require_fits(uint64_t(n), (binary_ ? 4 : 2) * values_each, what);
    return uint64_t(n);
  }
  double real(const char* what) {
    mid_line_ = !binary_;
    return binary_ ? double(in_.binary<float>(big_, what)) : in_.real(what);
  }
  // n values into out[0], out[stride], ...; a binary file's as one block.
  void reals(uint64_t n, const char* what, double* out, size_t stride) {
    if (!binary_) {
      for (uint64_t i = 0; i < n; ++i) out[i * stride] = real(what);
      return;
    }
    const char* bytes = in_.take(4 * n, what);
    for (uint64_t i = 0; i < n; ++i) out[i * stride] = double(load_value<float>(bytes + 4 * i, big_));
  }
  void integers(uint64_t n, const char* what, int64_t* out) {
    if (!binary_) {
      for (uint64_t i = 0; i < n; ++i) out[i] = integer(what);
      return;
    }
    const char* bytes = in_.take(4 * n, what);
    for (uint64_t i = 0; i < n; ++i) out[i] = load_value<int32_t>(bytes + 4 * i, big_);
  }
  // InputError unless `n` values fit in what is left of the file.
  void require_values(uint64_t n, const char* what) const { in_.require_fits(n, binary_ ? 4 : 2, what); }
  void skip_integers(uint64_t n, const char* what) {
    for (uint64_t i = 0; i < n; ++i) integer(what);
  }
  // Reads past n numbers of a part left out (--region): a binary file's as one block, a text
  // file's one by one (each must still be a number).
  void skip_numbers(uint64_t n, const char* what) {
    if (binary_) {
      in_.take(4 * n, what);
      return;
    }
    for (uint64_t i = 0; i < n; ++i) real(what);
  }
  // Text files: numbers one per line in the fixed-width formats, read as words; lines of
  // numbers run together (the extents) are skipped whole.
  void skip_lines(int n) {
    for (int i = 0; i < n; ++i) in_.skip_line();
  }
  bool binary() const { return binary_; }
  [[noreturn]] void fail(const std::string& what) const { in_.fail(what); }

 private:
  ParseCursor in_;
  bool binary_, big_;
  bool mid_line_ = false;  // text: the last thing read was a number, its line not yet ended
};

enum class IdMode { off, given, assign, ignore };
IdMode id_mode(const std::string& line, const char* prefix, const EnsightFile& f) {
  if (!line.starts_with(prefix))
    f.fail("expected '" + std::string(prefix) + " ...', found '" + line.substr(0, 40) + "'");
  const std::string mode = lower_trimmed(std::string_view(line).substr(std::string_view(prefix).size()));
  if (mode == "off") return IdMode::off;
  if (mode == "given") return IdMode::given;
  if (mode == "assign") return IdMode::assign;
  if (mode == "ignore") return IdMode::ignore;
  f.fail("unknown id mode '" + mode + "'");
}
bool ids_listed(IdMode m) { return m == IdMode::given || m == IdMode::ignore; }

struct ElementType {
  const char* name;
  int nodes;                        // 0: nsided and nfaced (their own counts)
  uint8_t vtk = 0;                  // 0: not a volume element, skipped
  std::array<uint8_t, 15> order{};  // VTK's node k is EnSight's node order[k] (when `reordered`)
  bool reordered = false;
};
// EnSight's penta6 and penta15 have their first triangle's normal towards the second; VTK's
// wedges the other way, so corners 1 and 2 (4 and 5) swap, and the mid-edge nodes with them.
// The other types list their nodes as VTK does.
constexpr ElementType kElementTypes[] = {
    {"point", 1},          {"bar2", 2},
    {"bar3", 3},           {"tria3", 3},
    {"tria6", 6},          {"quad4", 4},
    {"quad8", 8},          {"tetra4", 4, 10},
    {"pyramid5", 5, 14},   {"penta6", 6, 13, {0, 2, 1, 3, 5, 4}, true},
    {"hexa8", 8, 12},      {"nsided", 0},
    {"nfaced", 0, 42},     {"tetra10", 10, 24},
    {"pyramid13", 13, 27}, {"penta15", 15, 26, {0, 2, 1, 3, 5, 4, 8, 7, 6, 11, 10, 9, 12, 14, 13}, true},
    {"hexa20", 20, 25},
};

const ElementType* element_type(const std::string& keyword) {
  const std::string_view name =
      keyword.starts_with("g_") ? std::string_view(keyword).substr(2) : std::string_view(keyword);
  for (const ElementType& t : kElementTypes)
    if (name == t.name) return &t;
  return nullptr;
}

void read_coordinates(EnsightFile& f, IdMode nodes, EnsightGeometry::Part& part) {
  const uint64_t n = f.count("node count", 3);
  part.node_count = n;
  if (ids_listed(nodes)) f.skip_integers(n, "node ids");
  if (!part.wanted) {
    f.skip_numbers(3 * n, "coordinates");
    return;
  }
  part.mesh.points.resize(n);
  static_assert(sizeof(vec3d) == 3 * sizeof(double));
  for (int axis = 0; axis < 3 && n > 0; ++axis) f.reals(n, "coordinates", &part.mesh.points.data()->x + axis, 3);
}

// `count` 1-based node numbers, checked against the part's nodes, made 0-based.
std::vector<uint64_t> read_nodes(EnsightFile& f, uint64_t count, uint64_t part_nodes) {
  std::vector<int64_t> ids(count);
  f.integers(count, "element nodes", ids.data());
  std::vector<uint64_t> nodes(count);
  for (uint64_t i = 0; i < count; ++i) {
    if (ids[i] < 1 || uint64_t(ids[i]) > part_nodes)
      f.fail("element node " + std::to_string(ids[i]) + " is out of range (the part has " + str(part_nodes) +
             " nodes)");
    nodes[i] = uint64_t(ids[i] - 1);
  }
  return nodes;
}

// `keep`: into the part's mesh; else the nodes are only read past.
void add_fixed_block(EnsightFile& f, const ElementType& t, uint64_t count, bool keep, EnsightGeometry::Part& part) {
  if (!keep) {
    f.skip_numbers(count * uint64_t(t.nodes), "element nodes");
    return;
  }
  const std::vector<uint64_t> nodes = read_nodes(f, count * uint64_t(t.nodes), part.node_count);
  MeshData& m = part.mesh;
  for (uint64_t e = 0; e < count; ++e) {
    const uint64_t* v = nodes.data() + e * uint64_t(t.nodes);
    for (int k = 0; k < t.nodes; ++k) m.connectivity.push_back(t.reordered ? v[t.order[size_t(k)]] : v[k]);
    m.cell_types.push_back(t.vtk);
    m.cell_offsets.push_back(m.connectivity.size());
    part.faces.add_other_cell();
  }
}

// nsided: per element its node count, then the nodes. nfaced: per element its face count, per
// face its node count, then the faces' nodes.
void add_variable_block(EnsightFile& f, const ElementType& t, uint64_t count, bool keep, EnsightGeometry::Part& part) {
  const bool polyhedra = t.vtk == 42;
  std::vector<uint64_t> per_element(count), per_face;
  uint64_t faces = 0;
  for (uint64_t& c : per_element) {
    const int64_t v = f.integer(polyhedra ? "faces of an element" : "nodes of an element");
    if (v < 0 || v > (int64_t(1) << 30)) f.fail("bad count " + std::to_string(v) + " in an " + t.name + " block");
    c = uint64_t(v);
    faces += c;
  }
  f.require_values(faces, polyhedra ? "faces of nfaced elements" : "nodes of nsided elements");
  if (polyhedra) {
    per_face.resize(faces);
    uint64_t total = 0;
    for (uint64_t& c : per_face) {
      const int64_t v = f.integer("nodes of a face");
      if (v < 0 || v > (int64_t(1) << 30)) f.fail("bad node count " + std::to_string(v) + " of an nfaced face");
      c = uint64_t(v);
      total += c;
    }
    faces = total;
    f.require_values(faces, "nodes of nfaced faces");
  }
  if (!keep) {
    f.skip_numbers(faces, "element nodes");
    return;
  }
  const std::vector<uint64_t> nodes = read_nodes(f, faces, part.node_count);
  MeshData& m = part.mesh;
  uint64_t node = 0, face = 0;
  for (uint64_t e = 0; e < count; ++e) {
    std::vector<uint64_t> stream{per_element[e]};
    for (uint64_t k = 0; k < per_element[e]; ++k, ++face) {
      stream.push_back(per_face[face]);
      stream.insert(stream.end(), nodes.begin() + int64_t(node), nodes.begin() + int64_t(node + per_face[face]));
      node += per_face[face];
    }
    part.faces.add_face_stream(stream, m.cell_count(), f.name());
    m.cell_types.push_back(kVtkPolyhedron);
    m.cell_offsets.push_back(m.connectivity.size());
  }
}

void read_element_block(EnsightFile& f, const std::string& keyword, IdMode elements, EnsightGeometry::Part& part) {
  const ElementType* t = element_type(keyword);
  if (!t) f.fail("unknown element type '" + keyword.substr(0, 40) + "'");
  const bool volume = t->vtk != 0 && !keyword.starts_with("g_");
  const bool keep = volume && part.wanted;
  const uint64_t count = f.count("element count", uint64_t(std::max(t->nodes, 1) + (ids_listed(elements) ? 1 : 0)));
  if (ids_listed(elements)) f.skip_integers(count, "element ids");
  if (t->nodes > 0)
    add_fixed_block(f, *t, count, keep, part);
  else
    add_variable_block(f, *t, count, keep, part);
  part.blocks.push_back({keyword, count, keep});
}

// The first part number decides the byte order of a binary file: a small positive number one
// way round and not the other.
bool big_endian_part_number(const std::string& name, const std::string& bytes_of_file, uint64_t at) {
  if (at + 4 > bytes_of_file.size()) input_error(name, "the file ends before its first part");
  const int32_t little = load_value<int32_t>(bytes_of_file.data() + at, false);
  const int32_t big = load_value<int32_t>(bytes_of_file.data() + at, true);
  const auto plausible = [](int32_t v) { return v >= 0 && v < (1 << 24); };
  return !plausible(little) && plausible(big);
}

// Where the first "part" line's number lies in a binary geometry file, after the header lines
// and the optional extents.
uint64_t first_part_number_offset(const std::string& bytes) {
  uint64_t at = 80 * 5;  // "C Binary", two descriptions, node id, element id
  if (bytes.size() >= at + 80 && lower_trimmed(std::string_view(bytes).substr(at, 80)) == "extents") at += 80 + 24;
  return at + 80;
}

}  // namespace

EnsightCase read_ensight_case(const fs::path& file) {
  const std::string origin = file.string();
  const std::vector<CaseEntry> entries = case_entries(read_text_file(file, 16u << 20));
  EnsightCase c;
  c.dir = file.parent_path();
  bool gold = false, have_model = false;
  for (const CaseEntry& e : entries) {
    if (e.section == "FORMAT" && e.key == "type")
      gold = e.value.size() == 2 && lower_trimmed(e.value[0]) == "ensight" && lower_trimmed(e.value[1]) == "gold";
    if (e.section == "FILE") input_error(origin, "single-file cases (a FILE section) are not read");
    if (e.section == "GEOMETRY" && e.key == "model") {
      if (std::find(e.value.begin(), e.value.end(), "change_coords_only") != e.value.end())
        input_error(origin, "change_coords_only geometry is not read");
      c.geometry = file_ref(e.value, false, origin).file;
      have_model = true;
    }
    if (e.section == "VARIABLE" && !skipped_variable_kind(e.key)) c.variables.push_back(variable_of(e, origin));
  }
  input_check(gold, origin, "not an EnSight Gold case file (no 'type: ensight gold' in its FORMAT section)");
  input_check(have_model, origin, "no 'model:' geometry file in its GEOMETRY section");
  read_time_section(entries, c, origin);
  return c;
}

fs::path ensight_step_file(const EnsightCase& c, const std::string& name, size_t step) {
  std::string out = name;
  const size_t first = out.find('*');
  if (first != std::string::npos) {
    const size_t width = out.find_first_not_of('*', first) == std::string::npos
                             ? out.size() - first
                             : out.find_first_not_of('*', first) - first;
    std::string number = std::to_string(c.file_numbers.at(step));
    if (number.size() < width) number.insert(0, width - number.size(), '0');
    out.replace(first, width, number);
  }
  return c.dir / out;
}

namespace {

// --region: a part is read when one of the names asked for is its description or number (none
// asked for: every part); the others are read past.
bool answers_to(const EnsightGeometry::Part& p, const std::string& name) {
  return name == p.description || name == std::to_string(p.number);
}
bool asked_for(const EnsightGeometry::Part& p, const std::vector<std::string>& wanted) {
  return wanted.empty() ||
         std::any_of(wanted.begin(), wanted.end(), [&](const std::string& w) { return answers_to(p, w); });
}

// InputError for a name asked for that no part answers to, listing the parts.
void check_parts_found(const EnsightGeometry& g, const std::vector<std::string>& wanted, const std::string& file) {
  for (const std::string& w : wanted) {
    if (std::any_of(g.parts.begin(), g.parts.end(), [&](const EnsightGeometry::Part& p) { return answers_to(p, w); }))
      continue;
    std::vector<std::string> names;
    for (const EnsightGeometry::Part& p : g.parts)
      names.push_back(std::to_string(p.number) + (p.description.empty() ? "" : " (" + p.description + ")"));
    input_error(file, "no part '" + w + "' in this geometry (its parts: " + joined(names) + ")");
  }
}

}  // namespace

EnsightGeometry read_ensight_geometry(const fs::path& path, const std::vector<std::string>& parts) {
  EnsightGeometry g;
  {
    const uint64_t size = file_size_checked(path);
    std::string bytes(std::min<uint64_t>(size, 80 * 8), '\0');  // the header, the extents, the first part line
    read_exact(path, 0, bytes.data(), bytes.size());
    const std::string first = lower_trimmed(std::string_view(bytes).substr(0, std::min<size_t>(80, bytes.size())));
    if (first.starts_with("fortran binary"))
      input_error(path.string(), "Fortran binary EnSight files are not read (write C Binary)");
    g.binary = first.starts_with("c binary");
    if (g.binary) g.big_endian = big_endian_part_number(path.string(), bytes, first_part_number_offset(bytes));
  }
  EnsightFile f(path, g.binary, g.big_endian);
  if (g.binary) f.keyword();
  f.description();
  f.description();
  const IdMode nodes = id_mode(f.keyword(), "node id", f);
  const IdMode elements = id_mode(f.keyword(), "element id", f);
  if (f.peek_keyword() == "extents") {
    f.keyword();
    if (f.binary())
      for (int i = 0; i < 6; ++i) f.real("extents");
    else
      f.skip_lines(3);
  }
  while (!f.at_end()) {
    const std::string k = f.keyword();
    if (k != "part") f.fail("expected 'part', found '" + k.substr(0, 40) + "'");
    EnsightGeometry::Part part;
    part.number = f.integer("part number");
    part.description = f.description();
    part.wanted = asked_for(part, parts);
    const std::string what = f.keyword();
    if (what.starts_with("block")) f.fail("structured (block) parts are not read");
    if (what != "coordinates") f.fail("expected 'coordinates' in part " + std::to_string(part.number));
    read_coordinates(f, nodes, part);
    part.mesh.cell_offsets = {0};
    while (!f.at_end() && f.peek_keyword() != "part") read_element_block(f, f.keyword(), elements, part);
    g.parts.push_back(std::move(part));
  }
  input_check(!g.parts.empty(), path.string(), "no parts");
  check_parts_found(g, parts, path.string());
  return g;
}

namespace {

const EnsightGeometry::Part& part_numbered(const EnsightGeometry& g, int64_t number, const EnsightFile& f) {
  for (const EnsightGeometry::Part& p : g.parts)
    if (p.number == number) return p;
  f.fail("part " + std::to_string(number) + " is not in the geometry");
}

// `count` tuples of `components` values, stored component by component (all x, then all y, ...).
std::vector<double> read_tuples(EnsightFile& f, uint64_t count, int components, const char* what) {
  std::vector<double> values(count * uint64_t(components));
  for (int c = 0; c < components; ++c) f.reals(count, what, values.data() + c, size_t(components));
  return values;
}

// One variable file into each part's point or cell data (`arrays`: one per part, in the
// geometry's order; values for every kept cell or node of every part it lists, NaN, no data, for
// every one of a part it does not list, as a solid part without the fluid's velocity).
void read_variable(const EnsightCase::Variable& v, const fs::path& path, const EnsightGeometry& g,
                   std::vector<MeshArray>& arrays) {
  EnsightFile f(path, g.binary, g.big_endian);
  f.description();
  std::vector<bool> seen(g.parts.size(), false);
  while (!f.at_end()) {
    const std::string k = f.keyword();
    if (k != "part") f.fail("expected 'part', found '" + k.substr(0, 40) + "'");
    const EnsightGeometry::Part& part = part_numbered(g, f.integer("part number"), f);
    const size_t index = size_t(&part - g.parts.data());
    seen[index] = true;
    std::vector<double>& out = arrays[index].values;
    out.clear();
    const uint64_t components = uint64_t(v.components);
    if (!v.per_element) {
      const std::string c = f.keyword();
      if (c != "coordinates") f.fail("'" + c.substr(0, 40) + "': partial or undefined values are not read");
      if (part.wanted)
        out = read_tuples(f, part.node_count, v.components, "node value");
      else
        f.skip_numbers(part.node_count * components, "node value");
      continue;
    }
    for (const EnsightGeometry::Block& b : part.blocks) {
      const std::string type = f.keyword();
      if (type != b.type) f.fail("'" + type.substr(0, 40) + "' where the geometry has a block of " + b.type);
      if (!b.kept) {
        f.skip_numbers(b.count * components, "element value");
        continue;
      }
      const std::vector<double> values = read_tuples(f, b.count, v.components, "element value");
      out.insert(out.end(), values.begin(), values.end());
    }
  }
  for (size_t i = 0; i < g.parts.size(); ++i)
    if (!seen[i]) {
      const MeshData& m = g.parts[i].mesh;
      arrays[i].values.assign((v.per_element ? m.cell_count() : m.points.size()) * uint64_t(v.components), NAN);
    }
  if (std::find(seen.begin(), seen.end(), true) == seen.end()) f.fail("no values for any part");
}

}  // namespace

MeshData read_ensight_step(const EnsightCase& c, const EnsightGeometry& g, size_t step) {
  std::vector<MeshData> parts;
  for (const EnsightGeometry::Part& p : g.parts) parts.push_back(p.mesh);
  for (const EnsightCase::Variable& v : c.variables) {
    std::vector<MeshArray> arrays(g.parts.size(), MeshArray{v.name, v.components, {}});
    read_variable(v, ensight_step_file(c, v.file, step), g, arrays);
    for (size_t i = 0; i < parts.size(); ++i)
      (v.per_element ? parts[i].cell_data : parts[i].point_data).push_back(std::move(arrays[i]));
  }
  const std::string origin = ensight_step_file(c, c.geometry, step).string();
  std::vector<MeshData> volume;
  for (size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].cell_count() == 0 || !g.parts[i].wanted) continue;  // a boundary part, or one not asked for
    split_polyhedra(parts[i], g.parts[i].faces, origin, c.times.size() > 1 ? &g.parts[i].polyhedra_split : nullptr);
    volume.push_back(std::move(parts[i]));
  }
  input_check(!volume.empty(), origin,
              "no part has volume elements (tetra4, pyramid5, penta6, hexa8, nfaced, or the quadratic ones)" +
                  std::string(std::all_of(g.parts.begin(), g.parts.end(),
                                          [](const EnsightGeometry::Part& p) { return p.wanted; })
                                  ? ""
                                  : " among the parts asked for"));
  MeshData m = join_pieces(std::move(volume), origin);
  split_quadratic_cells(m, origin, c.times.size() > 1 ? &g.quadratic_split : nullptr);
  check_mesh(m, origin);
  return m;
}

}  // namespace vs
