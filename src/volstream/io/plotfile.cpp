#include "volstream/io/plotfile.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <mutex>
#include <numeric>
#include <set>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

// Limits on untrusted input: far above real plotfiles, low enough that nothing absurd is allocated.
constexpr int64_t kMaxComponents = 1 << 14;
constexpr int64_t kMaxBoxesPerLevel = int64_t(1) << 22;
constexpr int64_t kMaxGhost = 64;
constexpr int64_t kMaxIndex = int64_t(1) << 30;       // |index| in any Header or FAB box
constexpr uint64_t kMaxBoxCells = uint64_t(1) << 33;  // all boxes of all levels together
constexpr uint64_t kMaxLeafCells = uint64_t(1) << 32;
constexpr size_t kMaxFabHeaderBytes = 1024;
constexpr uint64_t kReadChunkBytes = uint64_t(4) << 20;  // per-task read buffer

std::string str(int64_t v) { return std::to_string(v); }
std::string str(uint64_t v) { return std::to_string(v); }
std::string str(int v) { return std::to_string(v); }

// ---------------------------------------------------------------------------------------------
// Inclusive index boxes, as AMReX writes them.

int64_t extent(const box3i& b, int axis) { return int64_t(b.upper[axis]) - b.lower[axis] + 1; }

// Saturates instead of overflowing, so that absurd boxes fail the size caps instead of wrapping.
uint64_t volume(const box3i& b) {
  if (b.empty()) return 0;
  uint64_t v = 1;
  for (int a = 0; a < 3; ++a) {
    const uint64_t e = uint64_t(extent(b, a));
    if (v > std::numeric_limits<uint64_t>::max() / 4 / e) return std::numeric_limits<uint64_t>::max() / 4;
    v *= e;
  }
  return v;
}

bool overlaps(const box3i& a, const box3i& b) {
  for (int axis = 0; axis < 3; ++axis)
    if (a.upper[axis] < b.lower[axis] || b.upper[axis] < a.lower[axis]) return false;
  return true;
}
bool inside(const box3i& b, const box3i& outer) { return outer.contains(b.lower) && outer.contains(b.upper); }
box3i intersection(const box3i& a, const box3i& b) { return {vmax(a.lower, b.lower), vmin(a.upper, b.upper)}; }
box3i grow(const box3i& b, const vec3i& n) { return {b.lower - n, b.upper + n}; }
// Coarsening by a power of two: an arithmetic shift is floor division, also for negative indices.
box3i coarsen(const box3i& b, int shift) {
  return {vec3i(b.lower.x >> shift, b.lower.y >> shift, b.lower.z >> shift),
          vec3i(b.upper.x >> shift, b.upper.y >> shift, b.upper.z >> shift)};
}
box3i refine(const box3i& b, int ratio) { return {b.lower * ratio, (b.upper + vec3i(1)) * ratio - vec3i(1)}; }

std::string vec_text(const vec3i& v) { return "(" + str(v.x) + "," + str(v.y) + "," + str(v.z) + ")"; }
// AMReX's Box notation: ((lower) (upper) (index type)); type (0,0,0) = cell-centred.
std::string box_text(const box3i& b) { return "(" + vec_text(b.lower) + " " + vec_text(b.upper) + " (0,0,0))"; }

// A static bounding-volume tree over boxes, to find the boxes a query box touches without
// comparing all pairs (levels can hold 10^5 boxes).
class BoxTree {
 public:
  explicit BoxTree(const std::vector<box3i>& boxes) : boxes_(boxes), order_(boxes.size()) {
    std::iota(order_.begin(), order_.end(), 0u);
    if (!boxes.empty()) build(0, uint32_t(boxes.size()));
  }
  // Calls visit(index) for every box that shares at least one cell with q.
  template <typename F>
  void query(const box3i& q, F&& visit) const {
    if (nodes_.empty()) return;
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
      const Node& n = nodes_[stack.back()];
      stack.pop_back();
      if (!overlaps(n.bounds, q)) continue;
      if (n.left == 0) {
        for (uint32_t i = n.begin; i < n.end; ++i)
          if (overlaps(boxes_[order_[i]], q)) visit(order_[i]);
      } else {
        stack.push_back(n.left);
        stack.push_back(n.right);
      }
    }
  }

 private:
  struct Node {
    box3i bounds;
    uint32_t begin, end;   // boxes order_[begin, end)
    uint32_t left, right;  // children; left == 0 marks a leaf (the root is never a child)
  };
  uint32_t build(uint32_t begin, uint32_t end) {
    const uint32_t self = uint32_t(nodes_.size());
    box3i bounds = box3i::make_empty();
    for (uint32_t i = begin; i < end; ++i) bounds.extend(boxes_[order_[i]]);
    nodes_.push_back({bounds, begin, end, 0, 0});
    if (end - begin <= 4) return self;
    const int axis = longest_axis(bounds);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](uint32_t a, uint32_t b) {
      return int64_t(boxes_[a].lower[axis]) + boxes_[a].upper[axis] <
             int64_t(boxes_[b].lower[axis]) + boxes_[b].upper[axis];
    });
    const uint32_t left = build(begin, mid);
    const uint32_t right = build(mid, end);
    nodes_[self].left = left;
    nodes_[self].right = right;
    return self;
  }
  static int longest_axis(const box3i& b) {
    const int64_t e[3] = {extent(b, 0), extent(b, 1), extent(b, 2)};
    return e[0] >= e[1] && e[0] >= e[2] ? 0 : (e[1] >= e[2] ? 1 : 2);
  }
  const std::vector<box3i>& boxes_;
  std::vector<uint32_t> order_;
  std::vector<Node> nodes_;
};

// ---------------------------------------------------------------------------------------------
// Text parsing: every read states what it expects, so garbage becomes "line N: expected ...".

class TextCursor {
 public:
  // `context` replaces the line number in messages (used for one-line FAB headers).
  TextCursor(std::string_view text, std::string file, std::string context = {})
      : text_(text), file_(std::move(file)), context_(std::move(context)) {}

  [[noreturn]] void fail(const std::string& what) const {
    const std::string where =
        context_.empty() ? "line " + str(int64_t(1 + std::count(text_.begin(), text_.begin() + pos_, '\n'))) : context_;
    input_error(file_, where + ": " + what);
  }
  char peek() {
    skip_space();
    return pos_ < text_.size() ? text_[pos_] : '\0';
  }
  void expect(char c, const std::string& what) {
    if (peek() != c) fail("expected '" + std::string(1, c) + "' in " + what);
    ++pos_;
  }
  std::string read_token(const std::string& what) {
    skip_space();
    const size_t begin = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    if (begin == pos_) fail("expected " + what + ", found the end of the file");
    return std::string(text_.substr(begin, pos_ - begin));
  }
  int64_t read_int(const std::string& what, int64_t lo, int64_t hi) {
    skip_plus();
    int64_t v = 0;
    const auto [end, ec] = std::from_chars(text_.data() + pos_, text_.data() + text_.size(), v);
    if (ec != std::errc()) fail("expected an integer (" + what + ")");
    if (v < lo || v > hi) fail(what + " " + str(v) + " is out of range [" + str(lo) + ", " + str(hi) + "]");
    pos_ = size_t(end - text_.data());
    return v;
  }
  double read_double(const std::string& what) {
    skip_plus();
    double v = 0;
    const auto [end, ec] = std::from_chars(text_.data() + pos_, text_.data() + text_.size(), v);
    if (ec != std::errc() || !std::isfinite(v)) fail("expected a finite number (" + what + ")");
    pos_ = size_t(end - text_.data());
    return v;
  }
  // The rest of the current line without surrounding spaces; the cursor moves past its newline.
  std::string read_line(const std::string& what) {
    if (pos_ >= text_.size()) fail("expected " + what + ", found the end of the file");
    size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view line = text_.substr(pos_, end - pos_);
    pos_ = std::min(end + 1, text_.size());
    while (!line.empty() && is_space(line.front())) line.remove_prefix(1);
    while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
    return std::string(line);
  }
  // Only spaces may follow on this line (a value that should stand alone, like the component count).
  void end_line(const std::string& what) {
    while (pos_ < text_.size() && text_[pos_] != '\n') {
      if (!is_space(text_[pos_])) fail("unexpected text after " + what);
      ++pos_;
    }
    if (pos_ < text_.size()) ++pos_;
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) ++pos_;
  }
  void skip_plus() {  // from_chars rejects a leading '+'
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == '+') ++pos_;
  }
  std::string_view text_;
  size_t pos_ = 0;
  std::string file_, context_;
};

vec3i read_int_vec(TextCursor& c, const std::string& what, int64_t lo, int64_t hi) {
  vec3i v;
  c.expect('(', what);
  for (int a = 0; a < 3; ++a) {
    if (a) c.expect(',', what);
    v[a] = int32_t(c.read_int(what, lo, hi));
  }
  c.expect(')', what);
  return v;
}

// "((lo) (hi) (type))"; only cell-centred boxes (type 0,0,0) make sense for cell data.
box3i read_box(TextCursor& c, const std::string& what) {
  c.expect('(', what);
  box3i b;
  b.lower = read_int_vec(c, what, -kMaxIndex, kMaxIndex);
  b.upper = read_int_vec(c, what, -kMaxIndex, kMaxIndex);
  if (!(read_int_vec(c, what, 0, 1) == vec3i(0))) c.fail(what + " is not cell-centred (index type is not (0,0,0))");
  c.expect(')', what);
  if (b.empty()) c.fail(what + " " + box_text(b) + " is empty (lower > upper)");
  return b;
}

// A plotfile version string: one word with a version tag, e.g. "HyperCLaw-V1.1" or "NavierStokes-V1.1".
bool looks_like_version(std::string_view line) {
  if (line.empty() || line.size() > 64 || !std::isalpha(static_cast<unsigned char>(line.front()))) return false;
  for (char ch : line)
    if (!std::isgraph(static_cast<unsigned char>(ch))) return false;
  return line.find("-V") != std::string_view::npos;
}

// A path inside the plotfile directory (no absolute paths, no "..").
bool is_inner_path(const std::string& s) {
  const fs::path p(s);
  if (s.empty() || p.is_absolute()) return false;
  for (const auto& part : p)
    if (part == ".." || part == ".") return false;
  return p.has_filename();
}

// ---------------------------------------------------------------------------------------------
// The plotfile Header.

struct PlotHeader {
  fs::path path;
  std::vector<std::string> names;
  double time = 0;
  int finest_level = 0;
  vec3d prob_lo, prob_hi;
  std::vector<int> ref_ratios;          // finest_level entries
  std::vector<box3i> domains;           // per level
  std::vector<int64_t> ngrids;          // per level
  std::vector<std::string> cell_paths;  // per level, e.g. "Level_0/Cell" (VisMF header = path + "_H")
};

void parse_components(TextCursor& c, PlotHeader& h) {
  if (!looks_like_version(c.read_line("version"))) c.fail("not a plotfile version string (like HyperCLaw-V1.1)");
  const int64_t ncomp = c.read_int("component count", 1, kMaxComponents);
  c.end_line("the component count");
  std::set<std::string> seen;
  for (int64_t i = 0; i < ncomp; ++i) {
    std::string name = c.read_line("component name");
    if (name.empty()) c.fail("empty component name");
    if (!seen.insert(name).second) c.fail("duplicate component name '" + name + "'");
    h.names.push_back(std::move(name));
  }
  if (c.read_int("space dimension", 1, 3) != 3) c.fail("only 3D plotfiles are supported");
  h.time = c.read_double("time");
  h.finest_level = int(c.read_int("finest level", 0, kMaxLevel));
}

void parse_geometry(TextCursor& c, PlotHeader& h) {
  const int levels = h.finest_level + 1;
  for (int a = 0; a < 3; ++a) h.prob_lo[a] = c.read_double("prob_lo");
  for (int a = 0; a < 3; ++a) h.prob_hi[a] = c.read_double("prob_hi");
  for (int a = 0; a < 3; ++a)
    if (!(h.prob_hi[a] > h.prob_lo[a])) c.fail("prob_hi is not above prob_lo on axis " + str(a));
  for (int l = 0; l < h.finest_level; ++l) {
    const int64_t r = c.read_int("ref ratio", 1, int64_t(1) << kMaxLevel);
    if (r < 2 || !std::has_single_bit(uint64_t(r))) c.fail("ref ratio " + str(r) + " is not a power of two >= 2");
    h.ref_ratios.push_back(int(r));
  }
  for (int l = 0; l < levels; ++l) h.domains.push_back(read_box(c, "level " + str(l) + " domain"));
  for (int l = 0; l < levels; ++l)
    c.read_int("level step", std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max());
  for (int l = 0; l < levels; ++l)
    for (int a = 0; a < 3; ++a)
      if (!(c.read_double("cell size") > 0)) c.fail("cell size is not positive");
  if (c.read_int("coordinate system", 0, 2) != 0) c.fail("only Cartesian coordinates (coord_sys 0) are supported");
  c.read_int("boundary width", 0, std::numeric_limits<int32_t>::max());
}

void parse_level_sections(TextCursor& c, PlotHeader& h) {
  for (int l = 0; l <= h.finest_level; ++l) {
    if (c.read_int("level number", 0, h.finest_level) != l) c.fail("expected the section of level " + str(l));
    const int64_t ngrids = c.read_int("grid count", l == 0 ? 1 : 0, kMaxBoxesPerLevel);
    c.read_double("level time");
    c.read_int("level step", std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max());
    for (int64_t g = 0; g < ngrids * 6; ++g) c.read_double("grid bounds");  // physical lo hi per axis
    std::string path = c.read_token("level data path");
    if (!is_inner_path(path)) c.fail("level data path '" + path + "' leaves the plotfile directory");
    h.ngrids.push_back(ngrids);
    h.cell_paths.push_back(std::move(path));
  }
}

PlotHeader parse_header(const fs::path& dir) {
  PlotHeader h;
  h.path = dir / "Header";
  const std::string text = read_text_file(h.path);
  TextCursor c(text, h.path.string());
  parse_components(c, h);
  parse_geometry(c, h);
  parse_level_sections(c, h);
  return h;
}

// log2 of each level's cell width in finest cells; also checks that the domains refine exactly.
std::vector<int> level_shifts(const PlotHeader& h) {
  const std::string file = h.path.string();
  std::vector<int> shift(h.domains.size(), 0);
  for (int l = h.finest_level - 1; l >= 0; --l) {
    shift[l] = shift[l + 1] + std::countr_zero(unsigned(h.ref_ratios[l]));
    if (shift[l] > kMaxLevel) input_error(file, "ref ratios multiply to more than 2^" + str(kMaxLevel));
  }
  for (int l = 0; l < h.finest_level; ++l) {
    const box3i& d = h.domains[l];
    const int64_t r = h.ref_ratios[l];
    for (int a = 0; a < 3; ++a) {
      const int64_t lo = int64_t(d.lower[a]) * r, hi = (int64_t(d.upper[a]) + 1) * r - 1;
      if (lo != h.domains[l + 1].lower[a] || hi != h.domains[l + 1].upper[a])
        input_error(file, "level " + str(l + 1) + " domain " + box_text(h.domains[l + 1]) + " is not level " + str(l) +
                              "'s domain refined by " + str(r));
    }
  }
  for (int a = 0; a < 3; ++a)
    if (extent(h.domains.back(), a) > kMaxCoord)
      input_error(file, "finest domain is too large (over 2^28 cells per axis)");
  return shift;
}

// Steps of a series must describe the same hierarchy; only time and data may differ.
void check_same_hierarchy(const PlotHeader& first, const PlotHeader& h) {
  const std::string file = h.path.string();
  if (h.names != first.names) input_error(file, "components differ from the first plotfile of the series");
  if (h.finest_level != first.finest_level || h.ref_ratios != first.ref_ratios)
    input_error(file, "levels or ref ratios differ from the first plotfile of the series");
  for (size_t l = 0; l < h.domains.size(); ++l)
    if (!(h.domains[l].lower == first.domains[l].lower && h.domains[l].upper == first.domains[l].upper))
      input_error(file, "level " + str(uint64_t(l)) + " domain differs from the first plotfile of the series");
  if (!(h.prob_lo == first.prob_lo && h.prob_hi == first.prob_hi))
    input_error(file, "prob_lo/prob_hi differ from the first plotfile of the series");
  if (h.ngrids != first.ngrids) input_error(file, "grid counts differ from the first plotfile of the series");
}

// ---------------------------------------------------------------------------------------------
// VisMF headers (Level_L/Cell_H): the BoxArray and where each box's FAB lies.

struct LevelFabs {
  fs::path header;  // the Cell_H file
  vec3i nghost{0, 0, 0};
  std::vector<box3i> boxes;
  std::vector<uint32_t> file;    // per box: index into StepFabs::files
  std::vector<uint64_t> offset;  // per box: byte offset of its FAB in that file
};

struct StepFabs {
  std::vector<fs::path> files;
  std::vector<LevelFabs> levels;
  std::unordered_map<std::string, uint32_t> file_index;

  uint32_t add_file(const fs::path& path) {
    const auto [it, added] = file_index.emplace(path.string(), uint32_t(files.size()));
    if (added) files.push_back(path);
    return it->second;
  }
};

vec3i read_nghost(TextCursor& c) {
  // Written as one number, or as an IntVect "(x,y,z)" when it differs per axis.
  if (c.peek() == '(') return read_int_vec(c, "ghost cells", 0, kMaxGhost);
  return vec3i(int32_t(c.read_int("ghost cells", 0, kMaxGhost)));
}

void read_box_array(TextCursor& c, int64_t ngrids, LevelFabs& lf) {
  c.expect('(', "BoxArray");
  const int64_t n = c.read_int("box count", 0, kMaxBoxesPerLevel);
  if (n != ngrids) c.fail("BoxArray has " + str(n) + " boxes, the Header says " + str(ngrids));
  c.read_int("BoxArray hash", std::numeric_limits<int64_t>::min(), std::numeric_limits<int64_t>::max());
  for (int64_t i = 0; i < n; ++i) lf.boxes.push_back(read_box(c, "box " + str(i)));
  c.expect(')', "BoxArray");
}

void read_fab_locations(TextCursor& c, const fs::path& level_dir, LevelFabs& lf, StepFabs& step) {
  const int64_t n = c.read_int("FabOnDisk count", 0, kMaxBoxesPerLevel);
  if (n != int64_t(lf.boxes.size()))
    c.fail(str(n) + " FabOnDisk entries for " + str(uint64_t(lf.boxes.size())) + " boxes");
  for (int64_t i = 0; i < n; ++i) {
    if (c.read_token("FabOnDisk:") != "FabOnDisk:") c.fail("expected 'FabOnDisk:'");
    const std::string name = c.read_token("FAB file name");
    if (name.find('/') != std::string::npos || !is_inner_path(name)) c.fail("bad FAB file name '" + name + "'");
    lf.file.push_back(step.add_file(level_dir / name));
    lf.offset.push_back(uint64_t(c.read_int("FAB offset", 0, std::numeric_limits<int64_t>::max())));
  }
}

LevelFabs parse_cell_header(const fs::path& path, int64_t ncomp, int64_t ngrids, StepFabs& step) {
  const std::string text = read_text_file(path);
  TextCursor c(text, path.string());
  LevelFabs lf;
  lf.header = path;
  const int64_t version = c.read_int("VisMF version", 0, 1 << 20);
  if (version != 1) c.fail("VisMF version " + str(version) + " is not supported (only version 1, with FAB headers)");
  c.read_int("VisMF 'how'", 0, 2);  // how the files were written; FabOnDisk says where each FAB is
  const int64_t n = c.read_int("component count", 0, kMaxComponents);
  if (n != ncomp) c.fail("holds " + str(n) + " components, the Header names " + str(ncomp));
  lf.nghost = read_nghost(c);
  read_box_array(c, ngrids, lf);
  read_fab_locations(c, path.parent_path(), lf, step);
  // Per-box min/max follow; they are not needed.
  return lf;
}

StepFabs parse_step_fabs(const fs::path& dir, const PlotHeader& h) {
  StepFabs step;
  for (size_t l = 0; l < h.cell_paths.size(); ++l) {
    const fs::path cell = dir / h.cell_paths[l];
    step.levels.push_back(
        parse_cell_header(fs::path(cell.string() + "_H"), int64_t(h.names.size()), h.ngrids[l], step));
  }
  // A FAB must start inside its file and the file must hold the box's values at 4 bytes each
  // at least (float32); checked before anything is allocated for the cells the boxes claim.
  // Its header and exact value size are checked when it is read.
  std::vector<uint64_t> sizes;
  for (const auto& f : step.files) sizes.push_back(file_size_checked(f));
  const uint64_t ncomp = h.names.size();
  for (const auto& lf : step.levels)
    for (size_t b = 0; b < lf.boxes.size(); ++b) {
      const uint64_t size = sizes[lf.file[b]], offset = lf.offset[b];
      const std::string file = step.files[lf.file[b]].string();
      if (offset >= size)
        input_error(
            file, "truncated: FAB offset " + str(offset) + " is beyond the end of the file (" + str(size) + " bytes)");
      const uint64_t need = volume(grow(lf.boxes[b], lf.nghost)) * ncomp * 4;
      if (need > size - offset)
        input_error(file, "truncated: the FAB at offset " + str(offset) + " needs at least " + str(need) +
                              " bytes, the file has " + str(size - offset) + " from there");
    }
  return step;
}

// ---------------------------------------------------------------------------------------------
// Hierarchy checks and the leaf layout.

// Boxes inside their domain, disjoint, fine boxes aligned to the ref ratio; total size capped.
void check_level_boxes(const LevelFabs& lf, const box3i& domain, int ratio_to_coarser, uint64_t& total_cells) {
  const std::string file = lf.header.string();
  for (size_t i = 0; i < lf.boxes.size(); ++i) {
    const box3i& b = lf.boxes[i];
    if (!inside(b, domain))
      input_error(file,
                  "box " + str(uint64_t(i)) + " " + box_text(b) + " lies outside the level domain " + box_text(domain));
    for (int a = 0; a < 3; ++a)
      if ((int64_t(b.lower[a]) - domain.lower[a]) % ratio_to_coarser != 0 ||
          (int64_t(b.upper[a]) + 1 - domain.lower[a]) % ratio_to_coarser != 0)
        input_error(file, "box " + str(uint64_t(i)) + " " + box_text(b) + " is not aligned to the ref ratio " +
                              str(ratio_to_coarser));
    total_cells += volume(b);
    if (total_cells > kMaxBoxCells) input_error(file, "too many cells (over 2^33 in all boxes)");
  }
  const BoxTree tree(lf.boxes);
  for (size_t i = 0; i < lf.boxes.size(); ++i)
    tree.query(lf.boxes[i], [&](uint32_t j) {
      if (j != i)
        input_error(file, "boxes " + str(uint64_t(std::min<size_t>(i, j))) + " and " +
                              str(uint64_t(std::max<size_t>(i, j))) + " overlap");
    });
}

// For each coarse box, the parts (in its index space) covered by the next finer level. Also checks
// proper nesting: every fine box must lie inside the union of the coarse boxes, or a finer leaf
// could overlap a coarse leaf that no box of the level in between removes.
std::vector<std::vector<box3i>> covered_regions(const LevelFabs& coarse, const LevelFabs& fine, int shift) {
  std::vector<std::vector<box3i>> covered(coarse.boxes.size());
  const BoxTree tree(coarse.boxes);
  for (size_t f = 0; f < fine.boxes.size(); ++f) {
    const box3i c = coarsen(fine.boxes[f], shift);
    uint64_t inside_cells = 0;
    tree.query(c, [&](uint32_t b) {
      const box3i part = intersection(c, coarse.boxes[b]);
      covered[b].push_back(part);
      inside_cells += volume(part);
    });
    if (inside_cells != volume(c))
      input_error(fine.header.string(),
                  "box " + str(uint64_t(f)) + " " + box_text(fine.boxes[f]) +
                      " is not inside the coarser level's boxes (levels must be properly nested)");
  }
  return covered;
}

// A run of leaf cells: `len` consecutive cells of a box in Fortran order, from linear index src.
struct Run {
  uint64_t src, len;
};

void append_run(std::vector<Run>& runs, uint64_t src, uint64_t len) {
  if (!runs.empty() && runs.back().src + runs.back().len == src)
    runs.back().len += len;  // continues across the row end: keep one run
  else
    runs.push_back({src, len});
}

// The uncovered cells of a box as runs: per row, the gaps between covered x-intervals.
std::vector<Run> leaf_runs(const box3i& box, const std::vector<box3i>& covered) {
  std::vector<Run> runs;
  if (covered.empty()) {
    runs.push_back({0, volume(box)});
    return runs;
  }
  const int64_t nx = extent(box, 0), ny = extent(box, 1), nz = extent(box, 2);
  struct Span {
    int64_t row, x0, x1;  // x0, x1 relative to box.lower.x, inclusive
  };
  std::vector<Span> spans;
  for (const box3i& c : covered)
    for (int64_t k = c.lower.z; k <= c.upper.z; ++k)
      for (int64_t j = c.lower.y; j <= c.upper.y; ++j)
        spans.push_back({(k - box.lower.z) * ny + (j - box.lower.y), c.lower.x - box.lower.x, c.upper.x - box.lower.x});
  std::sort(spans.begin(), spans.end(),
            [](const Span& a, const Span& b) { return a.row != b.row ? a.row < b.row : a.x0 < b.x0; });
  size_t s = 0;
  for (int64_t row = 0; row < ny * nz; ++row) {
    int64_t x = 0;
    for (; s < spans.size() && spans[s].row == row; ++s) {
      if (spans[s].x0 > x) append_run(runs, uint64_t(row * nx + x), uint64_t(spans[s].x0 - x));
      x = std::max(x, spans[s].x1 + 1);
    }
    if (x < nx) append_run(runs, uint64_t(row * nx + x), uint64_t(nx - x));
  }
  return runs;
}

// Where one box's leaves go: its runs are runs[first_run, first_run + run_count) and its first leaf
// has input index first_value.
struct BoxLayout {
  int32_t level;
  uint32_t index;  // within its level
  box3i box;
  uint64_t first_value, first_run, run_count;
};

// ---------------------------------------------------------------------------------------------
// Reading FABs.

inline float narrow(double v) {
  // Beyond float range becomes +-inf (a plain cast would be undefined there); NaN passes through.
  constexpr double kMax = std::numeric_limits<float>::max();
  if (v > kMax) return std::numeric_limits<float>::infinity();
  if (v < -kMax) return -std::numeric_limits<float>::infinity();
  return float(v);
}

struct FabFormat {
  int bytes = 8;  // 8: IEEE float64, 4: IEEE float32
  bool swap = false;
};

void convert(const unsigned char* src, uint64_t n, FabFormat fmt, float* dst) {
  if (fmt.bytes == 8) {
    for (uint64_t i = 0; i < n; ++i) {
      uint64_t u;
      std::memcpy(&u, src + i * 8, 8);
      if (fmt.swap) u = __builtin_bswap64(u);
      dst[i] = narrow(std::bit_cast<double>(u));
    }
  } else {
    for (uint64_t i = 0; i < n; ++i) {
      uint32_t u;
      std::memcpy(&u, src + i * 4, 4);
      if (fmt.swap) u = __builtin_bswap32(u);
      dst[i] = std::bit_cast<float>(u);
    }
  }
}

// "(n, (v1 ... vn))", as RealDescriptor writes its format and byte-order arrays. AMReX writes the
// array length as n; the entries are read up to ')' so that writers putting the byte count there
// are understood too.
std::vector<int64_t> read_descriptor_list(TextCursor& c) {
  c.expect('(', "real descriptor");
  c.read_int("descriptor length", 1, 16);
  c.expect(',', "real descriptor");
  c.expect('(', "real descriptor");
  std::vector<int64_t> v;
  while (c.peek() != ')') {
    if (v.size() == 16) c.fail("real descriptor list is too long");
    v.push_back(c.read_int("descriptor entry", -(1 << 20), 1 << 20));
  }
  c.expect(')', "real descriptor");
  c.expect(')', "real descriptor");
  return v;
}

FabFormat interpret_descriptor(TextCursor& c, const std::vector<int64_t>& format, const std::vector<int64_t>& order) {
  static const std::vector<int64_t> kDouble{64, 11, 52, 0, 1, 12, 0, 1023}, kFloat{32, 8, 23, 0, 1, 9, 0, 127};
  FabFormat fmt;
  if (format == kDouble)
    fmt.bytes = 8;
  else if (format == kFloat)
    fmt.bytes = 4;
  else
    c.fail("unsupported real format (only IEEE float64 and float32)");
  std::vector<int64_t> ascending(size_t(fmt.bytes));
  std::iota(ascending.begin(), ascending.end(), 1);
  const std::vector<int64_t> descending(ascending.rbegin(), ascending.rend());
  bool file_little;
  if (order == descending)
    file_little = true;  // "8 7 ... 1": least significant byte first
  else if (order == ascending)
    file_little = false;
  else
    c.fail("unsupported byte order");
  fmt.swap = file_little != (std::endian::native == std::endian::little);
  return fmt;
}

struct FabHeader {
  FabFormat format;
  box3i box;
  int64_t ncomp = 0;
  uint64_t length = 0;  // bytes of the header line, newline included
};

// "FAB ((8, (64 11 52 0 1 12 0 1023)),(8, (8 7 6 5 4 3 2 1)))((lo) (hi) (0,0,0)) ncomp\n"
FabHeader parse_fab_header(std::string_view bytes, const fs::path& file, uint64_t offset) {
  const size_t newline = bytes.find('\n');
  TextCursor c(bytes.substr(0, newline), file.string(), "FAB at offset " + str(offset));
  if (newline == std::string_view::npos) c.fail("no FAB header line");
  if (c.read_token("'FAB'") != "FAB") c.fail("expected 'FAB' (only binary FABs are supported)");
  FabHeader h;
  c.expect('(', "real descriptor");
  const auto format = read_descriptor_list(c);
  c.expect(',', "real descriptor");
  const auto order = read_descriptor_list(c);
  c.expect(')', "real descriptor");
  h.format = interpret_descriptor(c, format, order);
  h.box = read_box(c, "FAB box");
  h.ncomp = c.read_int("FAB component count", 1, kMaxComponents);
  c.end_line("the FAB header");
  h.length = newline + 1;
  return h;
}

void pread_exact(int fd, void* dst, uint64_t bytes, uint64_t offset, const fs::path& path) {
  auto* p = static_cast<unsigned char*>(dst);
  while (bytes > 0) {
    const ssize_t got = ::pread(fd, p, size_t(std::min<uint64_t>(bytes, uint64_t(1) << 30)), off_t(offset));
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) input_error(path.string(), "read error at offset " + str(offset) + ": " + std::strerror(errno));
    if (got == 0)
      input_error(path.string(), "truncated: expected " + str(bytes) + " more bytes at offset " + str(offset));
    p += got;
    bytes -= uint64_t(got);
    offset += uint64_t(got);
  }
}

// The data files of one step, open for the duration of one read_values call.
class OpenFiles {
 public:
  explicit OpenFiles(const std::vector<fs::path>& paths) {
    for (const auto& p : paths) {
      const int fd = ::open(p.c_str(), O_RDONLY | O_CLOEXEC);
      if (fd < 0) input_error(p.string(), "cannot open");
      fds_.push_back(fd);
      struct stat st {};
      if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) input_error(p.string(), "not a regular file");
      sizes_.push_back(uint64_t(st.st_size));
    }
  }
  ~OpenFiles() {
    for (int fd : fds_) ::close(fd);
  }
  OpenFiles(const OpenFiles&) = delete;
  OpenFiles& operator=(const OpenFiles&) = delete;
  int fd(uint32_t i) const { return fds_[i]; }
  uint64_t size(uint32_t i) const { return sizes_[i]; }

 private:
  std::vector<int> fds_;
  std::vector<uint64_t> sizes_;
};

// Reads elements of one component's slab through a chunk buffer: requests come in increasing
// order, so covered and ghost cells that span more than a chunk are skipped, not read.
class SlabReader {
 public:
  SlabReader(int fd, const fs::path& path, uint64_t start, uint64_t elems, FabFormat fmt,
             std::vector<unsigned char>& buf)
      : fd_(fd), path_(path), start_(start), elems_(elems), fmt_(fmt), buf_(buf) {}
  void copy(uint64_t at, uint64_t n, float* dst) {
    while (n > 0) {
      if (at < c0_ || at >= c1_) load(at);
      const uint64_t take = std::min(n, c1_ - at);
      convert(buf_.data() + (at - c0_) * uint64_t(fmt_.bytes), take, fmt_, dst);
      at += take;
      dst += take;
      n -= take;
    }
  }

 private:
  void load(uint64_t at) {
    c0_ = at;
    c1_ = std::min(elems_, at + kReadChunkBytes / uint64_t(fmt_.bytes));
    const uint64_t bytes = (c1_ - c0_) * uint64_t(fmt_.bytes);
    if (buf_.size() < bytes) buf_.resize(bytes);
    pread_exact(fd_, buf_.data(), bytes, start_ + c0_ * uint64_t(fmt_.bytes), path_);
  }
  int fd_;
  const fs::path& path_;
  uint64_t start_, elems_;
  FabFormat fmt_;
  std::vector<unsigned char>& buf_;
  uint64_t c0_ = 0, c1_ = 0;
};

// ---------------------------------------------------------------------------------------------

class PlotfileSource final : public AmrSource {
 public:
  explicit PlotfileSource(std::vector<fs::path> dirs) : dirs_(std::move(dirs)) {
    if (dirs_.empty()) throw UsageError("no plotfile directories given");
    for (size_t s = 0; s < dirs_.size(); ++s) {
      const PlotHeader h = parse_header(dirs_[s]);
      if (s == 0)
        first_ = h;
      else
        check_same_hierarchy(first_, h);
      times_.push_back(h.time);
      cell_paths_.push_back(h.cell_paths);
      auto fabs = std::make_shared<StepFabs>(parse_step_fabs(dirs_[s], h));
      if (s == 0)
        build_layout(*fabs);
      else
        check_same_boxes(*fabs);
      cached_step_ = int(s);
      cached_ = std::move(fabs);
    }
  }

  std::vector<Cell> take_cells() override {
    std::vector<Cell> cells(leaf_count_);
    parallel_for("plotfile cells", int64_t(boxes_.size()),
                 [&](int64_t b) { emit_cells(boxes_[size_t(b)], cells.data()); });
    return cells;
  }
  uint64_t cell_count() const override { return leaf_count_; }
  WorldTransform transform() const override {
    WorldTransform t;
    t.origin = first_.prob_lo;
    const box3i& finest = first_.domains.back();
    for (int a = 0; a < 3; ++a) t.cell_size[a] = (first_.prob_hi[a] - first_.prob_lo[a]) / double(extent(finest, a));
    return t;
  }
  std::vector<std::string> field_names() const override { return first_.names; }
  int step_count() const override { return int(dirs_.size()); }
  double step_time(int step) const override { return times_.at(size_t(step)); }
  void read_values(int field, int step, float* out) override;
  std::string description() const override {
    if (dirs_.size() == 1) return "AMReX plotfile " + dirs_.front().filename().string();
    return "AMReX plotfile series of " + str(uint64_t(dirs_.size())) + " steps from " +
           dirs_.front().filename().string();
  }
  std::string origin() const override { return first_.path.string(); }

 private:
  void build_layout(const StepFabs& fabs);
  void check_same_boxes(const StepFabs& fabs) const;
  std::shared_ptr<const StepFabs> step_fabs(int step);
  void emit_cells(const BoxLayout& b, Cell* out) const;
  void read_box(const BoxLayout& b, const LevelFabs& lf, const OpenFiles& files, const std::vector<fs::path>& paths,
                int field, float* out, std::vector<unsigned char>& buf) const;

  std::vector<fs::path> dirs_;
  PlotHeader first_;
  std::vector<double> times_;
  std::vector<std::vector<std::string>> cell_paths_;  // per step, per level
  std::vector<int> shift_;                            // per level: log2 of the cell width
  std::vector<std::vector<box3i>> level_boxes_;       // step 0's BoxArrays
  std::vector<BoxLayout> boxes_;                      // all levels, in input order
  std::vector<Run> runs_;
  uint64_t leaf_count_ = 0;

  std::mutex cache_mutex_;  // the FAB locations of the last step read
  int cached_step_ = -1;
  std::shared_ptr<const StepFabs> cached_;
};

void PlotfileSource::build_layout(const StepFabs& fabs) {
  shift_ = level_shifts(first_);
  const int levels = int(fabs.levels.size());
  uint64_t total_cells = 0;
  for (int l = 0; l < levels; ++l) {
    const int ratio = l == 0 ? 1 : first_.ref_ratios[size_t(l - 1)];
    check_level_boxes(fabs.levels[size_t(l)], first_.domains[size_t(l)], ratio, total_cells);
    level_boxes_.push_back(fabs.levels[size_t(l)].boxes);
  }
  for (int l = 0; l < levels; ++l) {
    const auto& boxes = level_boxes_[size_t(l)];
    std::vector<std::vector<box3i>> covered(boxes.size());
    if (l + 1 < levels)
      covered = covered_regions(fabs.levels[size_t(l)], fabs.levels[size_t(l + 1)],
                                shift_[size_t(l)] - shift_[size_t(l + 1)]);
    std::vector<std::vector<Run>> runs(boxes.size());
    parallel_for("plotfile leaf runs", int64_t(boxes.size()),
                 [&](int64_t b) { runs[size_t(b)] = leaf_runs(boxes[size_t(b)], covered[size_t(b)]); });
    for (size_t b = 0; b < boxes.size(); ++b) {
      BoxLayout layout{l, uint32_t(b), boxes[b], leaf_count_, runs_.size(), runs[b].size()};
      for (const Run& r : runs[b]) leaf_count_ += r.len;
      runs_.insert(runs_.end(), runs[b].begin(), runs[b].end());
      boxes_.push_back(layout);
    }
  }
  if (leaf_count_ > kMaxLeafCells)
    input_error(first_.path.string(), "too many leaf cells (" + str(leaf_count_) + ", the limit is 2^32)");
}

void PlotfileSource::check_same_boxes(const StepFabs& fabs) const {
  for (size_t l = 0; l < fabs.levels.size(); ++l) {
    const auto& a = fabs.levels[l].boxes;
    const auto& b = level_boxes_[l];
    bool same = a.size() == b.size();
    for (size_t i = 0; same && i < a.size(); ++i) same = a[i].lower == b[i].lower && a[i].upper == b[i].upper;
    if (!same) input_error(fabs.levels[l].header.string(), "boxes differ from the first plotfile of the series");
  }
}

std::shared_ptr<const StepFabs> PlotfileSource::step_fabs(int step) {
  std::lock_guard lock(cache_mutex_);
  if (step != cached_step_) {
    // Re-read the VisMF headers rather than keeping every step's FAB offsets in memory.
    PlotHeader h = first_;
    h.cell_paths = cell_paths_[size_t(step)];
    auto fabs = std::make_shared<StepFabs>(parse_step_fabs(dirs_[size_t(step)], h));
    check_same_boxes(*fabs);
    cached_step_ = step;
    cached_ = std::move(fabs);
  }
  return cached_;
}

void PlotfileSource::emit_cells(const BoxLayout& b, Cell* out) const {
  const int32_t shift = shift_[size_t(b.level)];
  const vec3i dlo = first_.domains[size_t(b.level)].lower;
  const int64_t nx = extent(b.box, 0), ny = extent(b.box, 1);
  uint64_t pos = b.first_value;
  for (uint64_t r = b.first_run; r < b.first_run + b.run_count; ++r) {
    const Run& run = runs_[r];
    int64_t i = int64_t(run.src) % nx, j = int64_t(run.src) / nx % ny, k = int64_t(run.src) / nx / ny;
    for (uint64_t n = 0; n < run.len; ++n) {
      const vec3i idx = b.box.lower + vec3i(int32_t(i), int32_t(j), int32_t(k));
      const vec3i g = idx - dlo;
      out[pos++] = {vec3i(g.x << shift, g.y << shift, g.z << shift), shift};
      if (++i == nx) {
        i = 0;
        if (++j == ny) j = 0, ++k;
      }
    }
  }
}

void PlotfileSource::read_box(const BoxLayout& b, const LevelFabs& lf, const OpenFiles& files,
                              const std::vector<fs::path>& paths, int field, float* out,
                              std::vector<unsigned char>& buf) const {
  const uint32_t fi = lf.file[b.index];
  const fs::path& path = paths[fi];
  const uint64_t offset = lf.offset[b.index], size = files.size(fi);
  if (offset >= size)
    input_error(path.string(), "truncated: FAB offset " + str(offset) + " is beyond the end of the file");
  std::string head(size_t(std::min<uint64_t>(kMaxFabHeaderBytes, size - offset)), '\0');
  pread_exact(files.fd(fi), head.data(), head.size(), offset, path);
  const FabHeader fab = parse_fab_header(head, path, offset);

  const box3i grown = grow(b.box, lf.nghost);
  const std::string where = "FAB at offset " + str(offset);
  if (!(fab.box.lower == grown.lower && fab.box.upper == grown.upper))
    input_error(path.string(), where + " has box " + box_text(fab.box) + ", " + lf.header.filename().string() +
                                   " says " + box_text(grown));
  if (fab.ncomp != int64_t(first_.names.size()))
    input_error(path.string(),
                where + " has " + str(fab.ncomp) + " components, expected " + str(uint64_t(first_.names.size())));
  const uint64_t elems = volume(grown), comp_bytes = elems * uint64_t(fab.format.bytes);
  const uint64_t data = offset + fab.length;
  if (data > size || (size - data) / uint64_t(fab.ncomp) < comp_bytes)
    input_error(path.string(),
                "truncated: " + where + " needs " + str(comp_bytes * uint64_t(fab.ncomp)) + " data bytes");

  SlabReader slab(files.fd(fi), path, data + uint64_t(field) * comp_bytes, elems, fab.format, buf);
  // Runs index the box without ghosts; with ghosts each row of a run lands elsewhere in the slab.
  const vec3i g = lf.nghost;
  const int64_t nx = extent(b.box, 0), ny = extent(b.box, 1);
  const int64_t gx = nx + 2 * g.x, gy = ny + 2 * g.y;
  uint64_t pos = b.first_value;
  for (uint64_t r = b.first_run; r < b.first_run + b.run_count; ++r) {
    const Run& run = runs_[r];
    if (g == vec3i(0)) {
      slab.copy(run.src, run.len, out + pos);
      pos += run.len;
      continue;
    }
    int64_t i = int64_t(run.src) % nx, j = int64_t(run.src) / nx % ny, k = int64_t(run.src) / nx / ny;
    for (uint64_t left = run.len; left > 0;) {
      const uint64_t take = std::min<uint64_t>(left, uint64_t(nx - i));
      slab.copy(uint64_t((i + g.x) + gx * ((j + g.y) + gy * (k + g.z))), take, out + pos);
      pos += take;
      left -= take;
      i = 0;
      if (++j == ny) j = 0, ++k;
    }
  }
}

void PlotfileSource::read_values(int field, int step, float* out) {
  if (field < 0 || field >= int(first_.names.size())) throw std::out_of_range("plotfile: field index out of range");
  if (step < 0 || step >= step_count()) throw std::out_of_range("plotfile: step index out of range");
  const auto fabs = step_fabs(step);
  const OpenFiles files(fabs->files);
  parallel_for_ranges(int64_t(boxes_.size()), [&](int64_t begin, int64_t end) {
    std::vector<unsigned char> buf;  // one per task, reused across its boxes
    for (int64_t b = begin; b < end; ++b) {
      const BoxLayout& layout = boxes_[size_t(b)];
      read_box(layout, fabs->levels[size_t(layout.level)], files, fabs->files, field, out, buf);
    }
  });
}

// ---------------------------------------------------------------------------------------------
// Writer.

void append_value(std::string& bytes, double v, bool float32, bool big_endian) {
  const bool swap = big_endian != (std::endian::native == std::endian::big);
  if (float32) {
    uint32_t u = std::bit_cast<uint32_t>(narrow(v));
    if (swap) u = __builtin_bswap32(u);
    bytes.append(reinterpret_cast<const char*>(&u), 4);
  } else {
    uint64_t u = std::bit_cast<uint64_t>(v);
    if (swap) u = __builtin_bswap64(u);
    bytes.append(reinterpret_cast<const char*>(&u), 8);
  }
}

std::string fab_header_line(const PlotfileSpec& spec, const box3i& box) {
  // As AMReX writes them: "(array length, (entries))" for the format, then for the byte order.
  std::string desc = spec.float32 ? "(8, (32 8 23 0 1 9 0 127)),(4, (" : "(8, (64 11 52 0 1 12 0 1023)),(8, (";
  desc += spec.float32 ? (spec.big_endian ? "1 2 3 4" : "4 3 2 1")
                       : (spec.big_endian ? "1 2 3 4 5 6 7 8" : "8 7 6 5 4 3 2 1");
  return "FAB (" + desc + ")))" + box_text(box) + " " + str(uint64_t(spec.components.size())) + "\n";
}

struct WrittenFab {
  std::string file;
  uint64_t offset;
  std::vector<double> min, max;  // per component, over the box without ghosts
};

// One FAB: header line, then each component's values, x fastest. Also its min/max per component.
WrittenFab write_fab(std::ofstream& out, const std::string& file, const PlotfileSpec& spec, int level, const box3i& box,
                     const std::function<double(int, int, int, int, int)>& value) {
  WrittenFab w{file, uint64_t(out.tellp()), {}, {}};
  const box3i grown = grow(box, vec3i(spec.nghost));
  out << fab_header_line(spec, grown);
  std::string bytes;
  for (int c = 0; c < int(spec.components.size()); ++c) {
    double lo = INFINITY, hi = -INFINITY;
    bytes.clear();
    for (int k = grown.lower.z; k <= grown.upper.z; ++k)
      for (int j = grown.lower.y; j <= grown.upper.y; ++j)
        for (int i = grown.lower.x; i <= grown.upper.x; ++i) {
          const double v = value(c, level, i, j, k);
          append_value(bytes, v, spec.float32, spec.big_endian);
          if (box.contains(vec3i(i, j, k))) lo = std::min(lo, v), hi = std::max(hi, v);
        }
    out.write(bytes.data(), std::streamsize(bytes.size()));
    w.min.push_back(lo);
    w.max.push_back(hi);
  }
  return w;
}

std::string cell_header_text(const PlotfileSpec& spec, const std::vector<box3i>& boxes,
                             const std::vector<WrittenFab>& fabs) {
  std::ostringstream h;
  h << "1\n0\n" << spec.components.size() << '\n' << spec.nghost << '\n';
  h << '(' << boxes.size() << " 0\n";
  for (const box3i& b : boxes) h << box_text(b) << '\n';
  h << ")\n" << fabs.size() << '\n';
  for (const auto& f : fabs) h << "FabOnDisk: " << f.file << ' ' << f.offset << '\n';
  h.setf(std::ios::scientific, std::ios::floatfield);
  h.precision(16);
  for (const bool want_min : {true, false}) {
    h << '\n' << fabs.size() << ',' << spec.components.size() << '\n';
    for (const auto& f : fabs) {
      for (double v : want_min ? f.min : f.max) h << v << ',';
      h << '\n';
    }
  }
  return h.str();
}

void close_checked(std::ofstream& out, const fs::path& path) {
  out.close();
  if (out.fail()) input_error(path.string(), "write failed (disk full?)");
}

void write_level(const fs::path& dir, const PlotfileSpec& spec, int level,
                 const std::function<double(int, int, int, int, int)>& value) {
  const fs::path level_dir = dir / ("Level_" + str(level));
  fs::create_directories(level_dir);
  const auto& boxes = spec.levels[size_t(level)].boxes;
  const size_t per_file = size_t(std::max(1, spec.boxes_per_fab_file));
  std::vector<WrittenFab> fabs;
  std::ofstream out;
  fs::path path;
  for (size_t b = 0; b < boxes.size(); ++b) {
    char name[32];
    std::snprintf(name, sizeof(name), "Cell_D_%05zu", b / per_file);
    if (b % per_file == 0) {
      if (out.is_open()) close_checked(out, path);
      path = level_dir / name;
      out.open(path, std::ios::binary | std::ios::trunc);
      if (!out) input_error(path.string(), "cannot open for writing");
    }
    fabs.push_back(write_fab(out, name, spec, level, boxes[b], value));
  }
  if (out.is_open()) close_checked(out, path);
  const std::string text = cell_header_text(spec, boxes, fabs);
  write_file(level_dir / "Cell_H", text.data(), text.size());
}

std::string plot_header_text(const PlotfileSpec& spec, const std::vector<box3i>& domains) {
  const int finest = int(spec.levels.size()) - 1;
  std::ostringstream h;
  h.precision(17);
  h << "HyperCLaw-V1.1\n" << spec.components.size() << '\n';
  for (const auto& name : spec.components) h << name << '\n';
  h << "3\n" << spec.time << '\n' << finest << '\n';
  for (int a = 0; a < 3; ++a) h << spec.prob_lo[a] << ' ';
  h << '\n';
  for (int a = 0; a < 3; ++a) h << spec.prob_hi[a] << ' ';
  h << '\n';
  for (int l = 0; l < finest; ++l) h << spec.ref_ratios[size_t(l)] << ' ';
  h << '\n';
  for (const box3i& d : domains) h << box_text(d) << ' ';
  h << '\n';
  for (int l = 0; l <= finest; ++l) h << "0 ";  // level steps
  h << '\n';
  std::vector<vec3d> dx;
  for (const box3i& d : domains) {
    dx.push_back((spec.prob_hi - spec.prob_lo) /
                 vec3d(double(extent(d, 0)), double(extent(d, 1)), double(extent(d, 2))));
    h << dx.back().x << ' ' << dx.back().y << ' ' << dx.back().z << ' ' << '\n';
  }
  h << "0\n0\n";  // Cartesian coordinates, boundary width
  for (int l = 0; l <= finest; ++l) {
    const auto& boxes = spec.levels[size_t(l)].boxes;
    h << l << ' ' << boxes.size() << ' ' << spec.time << '\n' << 0 << '\n';
    for (const box3i& b : boxes)
      for (int a = 0; a < 3; ++a)
        h << spec.prob_lo[a] + (b.lower[a] - domains[size_t(l)].lower[a]) * dx[size_t(l)][a] << ' '
          << spec.prob_lo[a] + (b.upper[a] + 1 - domains[size_t(l)].lower[a]) * dx[size_t(l)][a] << '\n';
    h << "Level_" << l << "/Cell\n";
  }
  return h.str();
}

}  // namespace

bool is_plotfile(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec) || !fs::is_regular_file(dir / "Header", ec)) return false;
  std::ifstream in(dir / "Header", std::ios::binary);
  char line[80] = {};
  in.getline(line, sizeof(line));
  std::string_view first(line);
  if (!first.empty() && first.back() == '\r') first.remove_suffix(1);
  return looks_like_version(first);
}

std::unique_ptr<AmrSource> open_plotfile_series(const std::vector<std::filesystem::path>& dirs) {
  return std::make_unique<PlotfileSource>(dirs);
}

void write_plotfile(const std::filesystem::path& dir, const PlotfileSpec& spec,
                    const std::function<double(int, int, int, int, int)>& value) {
  if (spec.levels.empty() || spec.ref_ratios.size() + 1 < spec.levels.size())
    throw std::invalid_argument("write_plotfile: needs at least one level and a ref ratio between each pair of levels");
  fs::create_directories(dir);
  std::vector<box3i> domains{spec.level0_domain};
  for (size_t l = 1; l < spec.levels.size(); ++l) domains.push_back(refine(domains.back(), spec.ref_ratios[l - 1]));
  for (int l = 0; l < int(spec.levels.size()); ++l) write_level(dir, spec, l, value);
  const std::string header = plot_header_text(spec, domains);
  write_file(dir / "Header", header.data(), header.size());
}

}  // namespace vs
