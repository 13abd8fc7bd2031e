#include "volstream/umesh/polyhedra.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>

#include "volstream/core/error.h"
#include "volstream/umesh/cell_rebuild.h"

namespace vs {
namespace {

std::string str(uint64_t v) { return std::to_string(v); }

// One element of a split polyhedron: a tet (4 vertices) or a pyramid (5) with the centroid last;
// or the polyhedron as the tet, pyramid, wedge (6) or hex (8) it is.
struct Piece {
  int count = 0;
  std::array<uint64_t, 8> v{};
};

CellType type_of(const Piece& p) {
  return p.count == 4   ? CellType::tet
         : p.count == 5 ? CellType::pyramid
         : p.count == 6 ? CellType::wedge
                        : CellType::hex;
}

vec3d mean_point(const MeshData& m, std::span<const uint64_t> v) {
  vec3d sum(0.0);
  for (uint64_t i : v) sum = sum + m.points[i];
  return sum * (1.0 / double(v.size()));
}

double box_extent(const MeshData& m, std::span<const uint64_t> v) {
  Box3<double> b{vec3d(INFINITY), vec3d(-INFINITY)};
  for (uint64_t i : v) b.extend(m.points[i]);
  return reduce_max(b.upper - b.lower);
}

// Positive when the piece is in VTK's orientation (a tet's first three corners, and a pyramid's
// base, seen from the last corner turn clockwise: their right-hand normal points to it); in
// units of length cubed, as a tet's six volumes.
double orientation(const MeshData& m, const Piece& p) {
  const vec3d* x = m.points.data();
  const vec3d& apex = x[p.v[p.count - 1]];
  if (p.count == 4) return dot(cross(x[p.v[1]] - x[p.v[0]], x[p.v[2]] - x[p.v[0]]), apex - x[p.v[0]]);
  const vec3d normal = cross(x[p.v[2]] - x[p.v[0]], x[p.v[3]] - x[p.v[1]]);
  const vec3d base = (x[p.v[0]] + x[p.v[1]] + x[p.v[2]] + x[p.v[3]]) * 0.25;
  return dot(normal, apex - base);
}

void reverse_base(Piece& p) {
  if (p.count == 4)
    std::swap(p.v[1], p.v[2]);
  else
    std::swap(p.v[1], p.v[3]);
}

void check_faces(const PolyhedronFaces& f, uint64_t cells, uint64_t points, const std::string& file) {
  auto check_csr = [&](const std::vector<uint64_t>& offsets, uint64_t rows, uint64_t entries, const char* what) {
    input_check(offsets.size() == rows + 1 && offsets.front() == 0 && offsets.back() == entries, file,
                std::string("polyhedra: the ") + what + " offsets do not span their array");
    for (uint64_t i = 1; i < offsets.size(); ++i)
      if (offsets[i] < offsets[i - 1]) input_error(file, std::string("polyhedra: the ") + what + " offsets decrease");
  };
  check_csr(f.cell_face_offsets, cells, f.cell_faces.size(), "cell face");
  const uint64_t faces = f.face_offsets.empty() ? 0 : f.face_offsets.size() - 1;
  check_csr(f.face_offsets, faces, f.face_vertices.size(), "face");
  check_face_index_count(faces, "polyhedron faces", file);  // so that a saturated id is out of range
  for (uint64_t id : f.cell_faces)
    if (id >= faces) input_error(file, "polyhedra: face id " + str(id) + " is out of range (" + str(faces) + " faces)");
  check_face_index_count(points, "points", file);
  for (uint64_t v : f.face_vertices)
    if (v >= points)
      input_error(file, "polyhedra: face vertex " + str(v) + " is out of range (" + str(points) + " points)");
}

// The mean of `vertices` as a new point of `m`, its data the mean of theirs (so that a field
// linear in space stays exact); returns its index.
uint64_t add_mean_point(MeshData& m, CellRebuild& cells, std::span<const uint64_t> vertices) {
  const std::vector<double> weights(vertices.size(), 1.0 / double(vertices.size()));
  return cells.add_point(m, vertices, weights);
}

// Splits one polyhedron at a time, adding its centroid and the centres of its faces of more
// than four vertices to the mesh's points; buffers are reused from one polyhedron to the next.
class PolyhedronSplitter {
 public:
  PolyhedronSplitter(MeshData& mesh, CellRebuild& cells, const PolyhedronFaces& faces, const std::string& file)
      : mesh_(mesh), cells_(cells), faces_(faces), file_(file) {}

  // Cell c's pieces, each in VTK's orientation.
  const std::vector<Piece>& split(uint64_t c) {
    cell_ = c;
    const uint64_t first = faces_.cell_face_offsets[c], end = faces_.cell_face_offsets[c + 1];
    if (end - first < 4) fail("has " + str(end - first) + " faces (a polyhedron needs 4 at least)");
    collect_vertices_and_edges(first, end);
    check_closed();
    pieces_.clear();
    if (as_element(first, end)) return pieces_;
    const uint64_t centroid = add_mean_point(mesh_, cells_, vertices_);
    for (uint64_t i = first; i < end; ++i) add_pieces(face(faces_.cell_faces[i]), centroid);
    orient();
    return pieces_;
  }

 private:
  std::span<const FaceIndex> face(uint64_t f) const {
    return std::span(faces_.face_vertices)
        .subspan(faces_.face_offsets[f], faces_.face_offsets[f + 1] - faces_.face_offsets[f]);
  }
  [[noreturn]] void fail(const std::string& why) const {
    input_error(file_, "polyhedron cell " + str(cell_) + " " + why);
  }

  void collect_vertices_and_edges(uint64_t first, uint64_t end) {
    vertices_.clear();
    edges_.clear();
    for (uint64_t i = first; i < end; ++i) {
      const std::span<const FaceIndex> v = face(faces_.cell_faces[i]);
      if (v.size() < 3) fail("has a face of " + str(v.size()) + " vertices");
      for (size_t k = 0; k < v.size(); ++k) {
        const uint64_t a = v[k], b = v[(k + 1) % v.size()];
        edges_.push_back({std::min(a, b), std::max(a, b), a < b});
        vertices_.push_back(a);
      }
    }
    std::sort(vertices_.begin(), vertices_.end());
    vertices_.erase(std::unique(vertices_.begin(), vertices_.end()), vertices_.end());
  }

  // Every edge in exactly two faces; oriented alike when it runs one way in one and the other
  // way in the other.
  void check_closed() {
    std::sort(edges_.begin(), edges_.end());
    oriented_alike_ = true;
    for (size_t i = 0; i < edges_.size();) {
      size_t j = i;
      while (j < edges_.size() && edges_[j].a == edges_[i].a && edges_[j].b == edges_[i].b) ++j;
      if (j - i != 2)
        fail("is not closed: its edge " + str(edges_[i].a) + "-" + str(edges_[i].b) + " is in " + str(j - i) +
             " of its faces, not 2");
      oriented_alike_ = oriented_alike_ && edges_[i].forward != edges_[i + 1].forward;
      i = j;
    }
  }

  // A polyhedron with the faces of a tet, a pyramid, a wedge or a hex, as Fluent's and CGNS's
  // polyhedral meshes (NFACE_n) give every cell, is that element, with VTK's shape functions and
  // no added point: the base is its quad (pyramid), its first triangle (tet, wedge) or its first
  // quad (hex), the rest the apex or the vertices across the side edges from the base's.
  bool as_element(uint64_t first, uint64_t end) {
    int triangles = 0, quads = 0;
    for (uint64_t i = first; i < end; ++i) {
      const size_t n = face(faces_.cell_faces[i]).size();
      if (n > 4) return false;
      (n == 4 ? quads : triangles)++;
    }
    const size_t faces = end - first, vertices = vertices_.size();
    const bool tet = faces == 4 && triangles == 4 && vertices == 4;
    const bool pyramid = faces == 5 && quads == 1 && vertices == 5;
    const bool wedge = faces == 5 && triangles == 2 && vertices == 6;
    const bool hex = faces == 6 && quads == 6 && vertices == 8;
    if (!(tet || pyramid || wedge || hex)) return false;
    const std::span<const FaceIndex> base = first_face_of(pyramid || hex ? 4 : 3, first, end);
    Piece p{int(vertices), {}};
    std::copy(base.begin(), base.end(), p.v.begin());
    for (size_t k = 0; k < base.size() && (wedge || hex); ++k) {
      const std::optional<uint64_t> across = neighbour_off(base[k], base);
      if (!across) return false;
      p.v[base.size() + k] = *across;
    }
    if (tet || pyramid)
      p.v[base.size()] = *std::find_if(vertices_.begin(), vertices_.end(), [&](uint64_t v) {
        return std::find(base.begin(), base.end(), v) == base.end();
      });
    if (!covers_vertices(p)) return false;
    pieces_.push_back(in_vtk_orientation(p));
    return true;
  }

  std::span<const FaceIndex> first_face_of(size_t vertices, uint64_t first, uint64_t end) const {
    for (uint64_t i = first; i < end; ++i)
      if (face(faces_.cell_faces[i]).size() == vertices) return face(faces_.cell_faces[i]);
    return {};
  }

  // The one vertex that shares an edge with v and is not in `base`; none if there are more.
  std::optional<uint64_t> neighbour_off(uint64_t v, std::span<const FaceIndex> base) const {
    std::optional<uint64_t> found;
    for (size_t i = 0; i < edges_.size(); i += 2) {  // each edge twice, once check_closed passed
      const Edge& e = edges_[i];
      if (e.a != v && e.b != v) continue;
      const uint64_t other = e.a == v ? e.b : e.a;
      if (std::find(base.begin(), base.end(), other) != base.end()) continue;
      if (found) return std::nullopt;
      found = other;
    }
    return found;
  }

  bool covers_vertices(const Piece& p) const {
    return std::is_permutation(p.v.begin(), p.v.begin() + p.count, vertices_.begin(), vertices_.end());
  }

  // VTK's orientation: a tet's first three corners and a pyramid's or hex's base have their
  // right-hand normal pointing to the rest, a wedge's first triangle away from the second.
  Piece in_vtk_orientation(Piece p) const {
    if (p.count <= 5) {
      if (orientation(mesh_, p) < 0) reverse_base(p);
      return p;
    }
    const size_t n = size_t(p.count / 2);
    const vec3d* x = mesh_.points.data();
    const vec3d normal = n == 3 ? cross(x[p.v[1]] - x[p.v[0]], x[p.v[2]] - x[p.v[0]])
                                : cross(x[p.v[2]] - x[p.v[0]], x[p.v[3]] - x[p.v[1]]);
    const double toward_top =
        dot(normal, mean_point(mesh_, std::span(p.v.data() + n, n)) - mean_point(mesh_, std::span(p.v.data(), n)));
    if ((n == 3 && toward_top > 0) || (n == 4 && toward_top < 0)) {
      std::reverse(p.v.begin() + 1, p.v.begin() + int64_t(n));
      std::reverse(p.v.begin() + int64_t(n) + 1, p.v.begin() + int64_t(2 * n));
    }
    return p;
  }

  // A triangle gives a tet, a quad a pyramid (its bilinear face is the neighbour's, whether that
  // is a hex, a wedge or another polyhedron); a face of more vertices a tet on each edge from
  // its centre, which the two polyhedra sharing the face share (a fan from one of its vertices
  // would make flat tets where three vertices lie on a line, as at a refinement step).
  void add_pieces(std::span<const FaceIndex> v, uint64_t centroid) {
    const size_t n = v.size();
    if (n == 3) return pieces_.push_back({4, {v[0], v[1], v[2], centroid}});
    if (n == 4) return pieces_.push_back({5, {v[0], v[1], v[2], v[3], centroid}});
    const uint64_t centre = face_centre(v);
    for (size_t k = 0; k < n; ++k) pieces_.push_back({4, {centre, v[k], v[(k + 1) % n], centroid}});
  }

  uint64_t face_centre(std::span<const FaceIndex> v) {
    key_.assign(v.begin(), v.end());
    std::sort(key_.begin(), key_.end());
    const auto [at, added] = face_centres_.try_emplace(key_, 0);
    if (added) at->second = add_mean_point(mesh_, cells_, key_);
    return at->second;
  }

  void orient() {
    int positive = 0, negative = 0;
    for (Piece& p : pieces_) {
      const double o = orientation(mesh_, p);
      const double extent = box_extent(mesh_, std::span(p.v.data(), size_t(p.count)));
      if (!(std::fabs(o) > 1e-9 * extent * extent * extent))
        fail(
            "gives a flat piece: a face of repeated or collinear vertices, or one in a plane through the vertex "
            "centroid (volstream splits a polyhedron from that centroid, so it must be star-shaped about it)");
      (o > 0 ? positive : negative)++;
      if (o < 0) reverse_base(p);
    }
    if (oriented_alike_ && positive && negative)
      fail("is not star-shaped about its vertex centroid (" + str(uint64_t(std::min(positive, negative))) + " of " +
           str(pieces_.size()) + " pieces of its faces are seen from it the wrong way round)");
  }

  // Sorted by its vertices alone: check_closed needs an edge's two sides side by side, in either
  // order, and the sort is most of its cost.
  struct Edge {
    uint64_t a, b;
    bool forward;
    bool operator<(const Edge& o) const { return a < o.a || (a == o.a && b < o.b); }
  };
  MeshData& mesh_;
  CellRebuild& cells_;
  const PolyhedronFaces& faces_;
  const std::string& file_;
  uint64_t cell_ = 0;
  bool oriented_alike_ = true;
  std::vector<uint64_t> vertices_, key_;
  std::vector<Edge> edges_;
  std::vector<Piece> pieces_;
  std::map<std::vector<uint64_t>, uint64_t> face_centres_;  // by the face's sorted vertices
};

}  // namespace

void check_face_index_count(uint64_t count, const char* what, const std::string& file) {
  // The message is built only on failure: add_face_stream asks once a face.
  if (count > kFaceIndexLimit)
    input_error(file,
                "more than 2^32 - 1 " + std::string(what) + " (polyhedra are read with 32-bit point and face ids)");
}

void PolyhedronFaces::add_face_stream(std::span<const uint64_t> stream, uint64_t cell, const std::string& file) {
  auto fail = [&](const std::string& why) {
    input_error(file, "polyhedron cell " + str(cell) + ": its face stream " + why);
  };
  if (stream.empty()) fail("is empty");
  const uint64_t count = stream[0];
  size_t pos = 1;
  for (uint64_t f = 0; f < count; ++f) {
    if (pos >= stream.size()) fail("ends before face " + str(f) + " of " + str(count));
    const uint64_t n = stream[pos++];
    if (n > stream.size() - pos) fail("ends inside face " + str(f));
    for (const uint64_t v : stream.subspan(pos, n)) {
      if (v >= kFaceIndexLimit) fail("names point " + str(v) + " (more than 32 bits)");
      face_vertices.push_back(FaceIndex(v));
    }
    face_offsets.push_back(face_vertices.size());
    check_face_index_count(face_offsets.size() - 1, "polyhedron faces", file);
    cell_faces.push_back(FaceIndex(face_offsets.size() - 2));
    pos += n;
  }
  if (pos != stream.size()) fail("holds " + str(stream.size() - pos) + " values after its " + str(count) + " faces");
  cell_face_offsets.push_back(cell_faces.size());
}

PolyhedronFaces faces_in_connectivity(const MeshData& m, const std::string& file) {
  PolyhedronFaces faces;
  for (uint64_t c = 0; c < m.cell_count() && c + 1 < m.cell_offsets.size(); ++c) {
    const uint64_t begin = m.cell_offsets[c], end = m.cell_offsets[c + 1];
    if (m.cell_types[c] == kVtkPolyhedron && begin <= end && end <= m.connectivity.size())
      faces.add_face_stream(std::span(m.connectivity).subspan(begin, end - begin), c, file);
    else
      faces.add_other_cell();
  }
  return faces;
}

PolyhedronFaces polyhedra_from_face_cells(std::vector<uint64_t> face_offsets, std::vector<FaceIndex> face_vertices,
                                          std::span<const FaceCells> face_cells, uint64_t cell_count,
                                          const std::string& file) {
  check_face_index_count(face_cells.size(), "faces", file);
  PolyhedronFaces p;
  p.face_offsets = std::move(face_offsets);
  p.face_vertices = std::move(face_vertices);
  p.cell_face_offsets.assign(cell_count + 1, 0);
  for (const FaceCells& f : face_cells)
    for (uint64_t c : {f.first, f.second}) {
      if (c > cell_count) input_error(file, "a face names cell " + str(c) + " of " + str(cell_count));
      if (c != 0) ++p.cell_face_offsets[c];
    }
  for (uint64_t c = 0; c < cell_count; ++c) p.cell_face_offsets[c + 1] += p.cell_face_offsets[c];
  p.cell_faces.resize(p.cell_face_offsets.back());
  std::vector<uint64_t> next(p.cell_face_offsets.begin(), p.cell_face_offsets.end() - 1);
  for (uint64_t f = 0; f < face_cells.size(); ++f)
    for (uint64_t c : {face_cells[f].first, face_cells[f].second})
      if (c != 0) p.cell_faces[next[c - 1]++] = FaceIndex(f);
  return p;
}

namespace {

bool has_polyhedra(const MeshData& m) {
  return std::find(m.cell_types.begin(), m.cell_types.end(), kVtkPolyhedron) != m.cell_types.end();
}

// The cells of `m` with its polyhedra split, their added points already in m.points.
CellRebuild split_cells(MeshData& m, const PolyhedronFaces& faces, const std::string& file) {
  check_faces(faces, m.cell_count(), m.points.size(), file);
  check_rebuild_input(m, "polyhedra", file);
  CellRebuild cells;
  PolyhedronSplitter splitter(m, cells, faces, file);
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    if (m.cell_types[c] != kVtkPolyhedron) {
      cells.keep(m, c);
      continue;
    }
    for (const Piece& p : splitter.split(c)) cells.add(uint8_t(type_of(p)), std::span(p.v.data(), size_t(p.count)), c);
  }
  return cells;
}

}  // namespace

void split_polyhedra(MeshData& m, const PolyhedronFaces& faces, const std::string& file, SplitMemo* memo) {
  if (!has_polyhedra(m)) return;
  const auto key = faces.key();
  if (memo && memo->reuse(m, key, file)) return;
  if (memo) memo->split_begins(m, key);
  CellRebuild cells = split_cells(m, faces, file);
  if (!memo) return std::move(cells).finish(m);
  cells.finish(m);
  memo->split_ends(std::move(cells), m.points);
}

FixedMeshSplit::FixedMeshSplit(MeshData unsplit, const PolyhedronFaces& faces, const std::string& file)
    : mesh_(std::move(unsplit)), unsplit_points_(mesh_.points.size()), unsplit_cells_(mesh_.cell_count()) {
  if (!has_polyhedra(mesh_)) return;  // nothing to split: the data stay as they are
  rebuild_ = split_cells(mesh_, faces, file);
  rebuild_->move_cells(mesh_);
}

void FixedMeshSplit::check_not_taken() const {
  if (taken_) throw std::logic_error("FixedMeshSplit: the split mesh was taken already");
}

MeshData FixedMeshSplit::mesh_with(std::vector<MeshArray> cell_data, const std::string& file) const {
  check_not_taken();
  MeshData m = mesh_;
  m.cell_data = std::move(cell_data);
  check_mesh(m, file);
  return m;
}

MeshData FixedMeshSplit::take_mesh_with(std::vector<MeshArray> cell_data, const std::string& file) {
  check_not_taken();
  taken_ = true;
  MeshData m = std::move(mesh_);
  m.cell_data = std::move(cell_data);
  check_mesh(m, file);
  return m;
}

void FixedMeshSplit::split_data(std::vector<MeshArray>& point_data, std::vector<MeshArray>& cell_data,
                                const std::string& file) const {
  input_check(arrays_match(point_data, unsplit_points_) && arrays_match(cell_data, unsplit_cells_), file,
              "a data array does not match the mesh's points or cells");
  if (rebuild_) rebuild_->finish_data(point_data, cell_data);
}

}  // namespace vs
