#include "volstream/umesh/quadratic.h"

#include <algorithm>
#include <array>
#include <map>
#include <span>
#include <vector>

#include "volstream/core/error.h"
#include "volstream/umesh/cell_rebuild.h"

namespace vs {
namespace {

constexpr auto kTet = uint8_t(CellType::tet), kHex = uint8_t(CellType::hex), kWedge = uint8_t(CellType::wedge),
               kPyramid = uint8_t(CellType::pyramid);

// A node a quadratic cell lacks, at -1/4 of each of its `corners` nodes and `mid_weight` of each of
// its `mids` (VTK's shape functions there): a serendipity quad face's centre (4 corners, 4 mid-edge
// nodes at 1/2), shared with the cell across the face, or a hex's body centre.
struct Centre {
  std::array<uint8_t, 8> corner;
  std::array<uint8_t, 12> mid;
  uint8_t corners, mids;
  double mid_weight;
  bool on_face;
};

constexpr Centre face(std::array<uint8_t, 4> c, std::array<uint8_t, 4> m) {
  return {{c[0], c[1], c[2], c[3]}, {m[0], m[1], m[2], m[3]}, 4, 4, 0.5, true};
}

// The hex27's face centres 20-25 (faces x = 0, x = 1, y = 0, y = 1, z = 0, z = 1 of the
// parametric cube) from a hex20's nodes, then its body centre 26.
constexpr std::array<Centre, 7> kHex20Centres = {
    face({0, 3, 4, 7}, {11, 15, 16, 19}),
    face({1, 2, 5, 6}, {9, 13, 17, 18}),
    face({0, 1, 4, 5}, {8, 12, 16, 17}),
    face({2, 3, 6, 7}, {10, 14, 18, 19}),
    face({0, 1, 2, 3}, {8, 9, 10, 11}),
    face({4, 5, 6, 7}, {12, 13, 14, 15}),
    Centre{{0, 1, 2, 3, 4, 5, 6, 7}, {8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19}, 8, 12, 0.25, false}};
// A hex24 has the side faces' centres (20-23); its faces z = 0 and z = 1 are serendipity quads,
// and its body centre is the centre of the quad of its mid-height nodes 16-19 and 20-23.
constexpr std::array<Centre, 3> kHex24Centres = {face({0, 1, 2, 3}, {8, 9, 10, 11}),
                                                 face({4, 5, 6, 7}, {12, 13, 14, 15}),
                                                 Centre{{16, 17, 18, 19}, {20, 21, 22, 23}, 4, 4, 0.5, false}};
// The wedge18's quad face centres 15-17 from a wedge15's nodes.
constexpr std::array<Centre, 3> kWedge15Centres = {
    face({0, 1, 3, 4}, {6, 9, 12, 13}), face({1, 2, 4, 5}, {7, 10, 13, 14}), face({0, 2, 3, 5}, {8, 11, 12, 14})};
// A pyramid13's base centre (node 13 of its split).
constexpr std::array<Centre, 1> kPyramid13Centres = {face({0, 1, 2, 3}, {5, 6, 7, 8})};

// A Lagrange hexahedron of order p (VTK 9.1's node order, the triquadratic hexahedron's at p = 2):
// the index of its node at lattice point (i, j, k), each in 0..p. Corners first, then the p - 1
// nodes inside each edge (edges 0-1, 1-2, 3-2, 0-3, 4-5, 5-6, 7-6, 4-7, 0-4, 1-5, 2-6, 3-7, each
// along its axis), then the (p - 1)^2 inside each face (x = 0, x = p, y = 0, y = p, z = 0,
// z = p; the lower axis fastest), then the (p - 1)^3 inside the cell (x fastest).
constexpr uint32_t lagrange_hex_node(int i, int j, int k, int p) {
  const bool on_i = i == 0 || i == p, on_j = j == 0 || j == p, on_k = k == 0 || k == p;
  // The corner of a unit square's (x, y) in VTK's order 0, 1, 2, 3.
  const auto corner = [](bool x, bool y) { return x ? (y ? 2 : 1) : (y ? 3 : 0); };
  const int m = p - 1;
  const int on = int(on_i) + int(on_j) + int(on_k);
  if (on == 3) return uint32_t(corner(i != 0, j != 0) + (k != 0 ? 4 : 0));
  if (on == 2) {
    const int edge = !on_i   ? (j != 0 ? 2 : 0) + (k != 0 ? 4 : 0)
                     : !on_j ? (i != 0 ? 1 : 3) + (k != 0 ? 4 : 0)
                             : 8 + corner(i != 0, j != 0);
    const int along = !on_i ? i : !on_j ? j : k;
    return uint32_t(8 + edge * m + along - 1);
  }
  const int faces = 8 + 12 * m;
  if (on == 1) {
    const int face = on_i ? (i != 0 ? 1 : 0) : on_j ? (j != 0 ? 3 : 2) : (k != 0 ? 5 : 4);
    const int a = on_i ? j : i, b = on_k ? j : k;
    return uint32_t(faces + face * m * m + (a - 1) + m * (b - 1));
  }
  return uint32_t(faces + 6 * m * m + (i - 1) + m * ((j - 1) + m * (k - 1)));
}
constexpr uint8_t kHexCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                      {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
constexpr int kMaxLagrangeOrder = 10;  // 1,331 nodes a hexahedron

// The order of a Lagrange hexahedron of `nodes` nodes ((p + 1)^3) and of a Lagrange tetra
// ((p + 1)(p + 2)(p + 3) / 6); 0 if none up to the largest.
int lagrange_hex_order(uint64_t nodes) {
  for (int p = 1; p <= kMaxLagrangeOrder; ++p)
    if (uint64_t((p + 1) * (p + 1) * (p + 1)) == nodes) return p;
  return 0;
}
int lagrange_tet_order(uint64_t nodes) {
  for (int p = 1; p <= kMaxLagrangeOrder; ++p)
    if (uint64_t((p + 1) * (p + 2) * (p + 3) / 6) == nodes) return p;
  return 0;
}

// The wedge18's nodes by layer (bottom, mid-height, top), each as its triangle's corners a, b, c
// and its mid-edge nodes ab, bc, ca; and the four triangles of a layer, by those positions.
constexpr uint8_t kWedge18Layer[3][6] = {{0, 1, 2, 6, 7, 8}, {12, 13, 14, 15, 16, 17}, {3, 4, 5, 9, 10, 11}};
constexpr uint8_t kLayerTriangle[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};

// The octahedron between a tet10's corner tets (its nodes 4-9), as four tets around each of its
// diagonals 4-9, 5-7 and 6-8 (each in VTK's orientation, as the cell is).
constexpr uint8_t kTet10Diagonal[3][2] = {{4, 9}, {5, 7}, {6, 8}};
constexpr uint8_t kTet10Octahedron[3][4][4] = {{{4, 9, 5, 6}, {4, 9, 6, 7}, {4, 9, 7, 8}, {4, 9, 8, 5}},
                                               {{5, 7, 6, 4}, {5, 7, 9, 6}, {5, 7, 8, 9}, {5, 7, 4, 8}},
                                               {{6, 8, 4, 5}, {6, 8, 5, 9}, {6, 8, 9, 7}, {6, 8, 7, 4}}};

// A Lagrange tetra of order p in VTK's node order (the quadratic tetra's at p = 2), as the lattice
// points (i, j, k) of its nodes: i, j, k steps of 1/p from corner 0 towards corners 1, 2, 3
// (i + j + k <= p). Corners, then the p - 1 nodes inside each edge (0-1, 1-2, 2-0, 0-3, 1-3, 2-3,
// from the first corner), then the nodes inside each face (0-1-3, 2-3-1, 0-3-2, 0-2-1, each a
// triangle of order p - 3 in this same order: corners, edges, inside), then those inside the
// tetra, a tetra of order p - 4.
using Lattice = std::array<int, 3>;

Lattice step(const Lattice& from, const Lattice& to, int steps) {  // 1/steps of the way
  return {(to[0] - from[0]) / steps, (to[1] - from[1]) / steps, (to[2] - from[2]) / steps};
}
Lattice plus(Lattice a, const Lattice& b, int times = 1) {
  for (int d = 0; d < 3; ++d) a[size_t(d)] += times * b[size_t(d)];
  return a;
}

void triangle_lattice(const Lattice& a, const Lattice& b, const Lattice& c, int order, std::vector<Lattice>& out) {
  if (order < 0) return;
  if (order == 0) return out.push_back(a);
  out.insert(out.end(), {a, b, c});
  const Lattice ab = step(a, b, order), bc = step(b, c, order), ca = step(c, a, order);
  for (const auto& [from, along] : {std::pair{a, ab}, std::pair{b, bc}, std::pair{c, ca}})
    for (int t = 1; t < order; ++t) out.push_back(plus(from, along, t));
  // the inside: each corner one step in along both its edges
  triangle_lattice(plus(plus(a, ab), ca, -1), plus(plus(b, bc), ab, -1), plus(plus(c, ca), bc, -1), order - 3, out);
}

void tetra_lattice(const std::array<Lattice, 4>& v, int order, std::vector<Lattice>& out) {
  if (order < 0) return;
  if (order == 0) return out.push_back(v[0]);
  out.insert(out.end(), v.begin(), v.end());
  constexpr int kEdges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  for (const auto& e : kEdges)
    for (int t = 1; t < order; ++t)
      out.push_back(plus(v[size_t(e[0])], step(v[size_t(e[0])], v[size_t(e[1])], order), t));
  // a face's (or the tetra's) inside: each of its corners one step towards each of its others
  const auto inward = [&](int corner, std::initializer_list<int> others) {
    Lattice p = v[size_t(corner)];
    for (int o : others) p = plus(p, step(v[size_t(corner)], v[size_t(o)], order));
    return p;
  };
  constexpr int kFaces[4][3] = {{0, 1, 3}, {2, 3, 1}, {0, 3, 2}, {0, 2, 1}};
  for (const auto& f : kFaces)
    triangle_lattice(inward(f[0], {f[1], f[2]}), inward(f[1], {f[0], f[2]}), inward(f[2], {f[0], f[1]}), order - 3,
                     out);
  tetra_lattice({inward(0, {1, 2, 3}), inward(1, {0, 2, 3}), inward(2, {0, 1, 3}), inward(3, {0, 1, 2})}, order - 4,
                out);
}

// The node index of each lattice point of a Lagrange tetra of order p, at (i * (p + 1) + j) * (p + 1) + k.
std::vector<uint32_t> tetra_node_table(int p) {
  std::vector<Lattice> nodes;
  tetra_lattice({Lattice{0, 0, 0}, Lattice{p, 0, 0}, Lattice{0, p, 0}, Lattice{0, 0, p}}, p, nodes);
  std::vector<uint32_t> table(size_t((p + 1) * (p + 1) * (p + 1)), 0);
  for (size_t n = 0; n < nodes.size(); ++n)
    table[size_t((nodes[n][0] * (p + 1) + nodes[n][1]) * (p + 1) + nodes[n][2])] = uint32_t(n);
  return table;
}

// A pyramid with its base centre (node 13): a pyramid on each quarter of the base, one on the
// quad of the side edges' mid-nodes up to the apex and one down to the base centre, and a tet
// between each side's two.
constexpr uint8_t kPyramid14Pyramids[6][5] = {{0, 5, 13, 8, 9},  {5, 1, 6, 13, 10},  {13, 6, 2, 7, 11},
                                              {8, 13, 7, 3, 12}, {9, 10, 11, 12, 4}, {9, 12, 11, 10, 13}};
constexpr uint8_t kPyramid14Tets[4][4] = {{5, 13, 9, 10}, {6, 13, 10, 11}, {7, 13, 11, 12}, {8, 13, 12, 9}};

std::span<const Centre> centres_of(uint8_t type) {
  switch (QuadraticCell(type)) {
    case QuadraticCell::hex20:
      return kHex20Centres;
    case QuadraticCell::hex24:
      return kHex24Centres;
    case QuadraticCell::wedge15:
      return kWedge15Centres;
    case QuadraticCell::pyramid13:
      return kPyramid13Centres;
    default:
      return {};
  }
}

// Splits one quadratic cell at a time; face centres are kept by their nodes, for the cell on the
// face's other side.
class QuadraticSplitter {
 public:
  QuadraticSplitter(MeshData& mesh, CellRebuild& cells) : mesh_(mesh), cells_(cells) {}

  void split(uint64_t c) {
    const uint8_t type = mesh_.cell_types[c];
    const auto begin = mesh_.connectivity.begin() + int64_t(mesh_.cell_offsets[c]);
    nodes_.assign(begin, mesh_.connectivity.begin() + int64_t(mesh_.cell_offsets[c + 1]));
    for (const Centre& centre : centres_of(type)) nodes_.push_back(add_centre(centre));
    switch (QuadraticCell(type)) {
      case QuadraticCell::tet10:
        return split_lagrange_tet(c, 2);
      case QuadraticCell::lagrange_tet:
        return split_lagrange_tet(c, lagrange_tet_order(nodes_.size()));
      case QuadraticCell::hex20:
      case QuadraticCell::hex24:
      case QuadraticCell::hex27:
        return split_lagrange_hex(c, 2);
      case QuadraticCell::lagrange_hex:
        return split_lagrange_hex(c, lagrange_hex_order(nodes_.size()));
      case QuadraticCell::wedge15:
      case QuadraticCell::wedge18:
        return split_wedge18(c);
      case QuadraticCell::pyramid13:
        return split_pyramid14(c);
    }
  }

 private:
  template <size_t N>
  void add(uint8_t type, const uint8_t (&local)[N], uint64_t c) {
    std::array<uint64_t, N> v;
    for (size_t k = 0; k < N; ++k) v[k] = nodes_[local[k]];
    cells_.add(type, v, c);
  }

  uint64_t add_centre(const Centre& centre) {
    vertices_.clear();
    weights_.clear();
    for (int k = 0; k < centre.corners; ++k) {
      vertices_.push_back(nodes_[centre.corner[size_t(k)]]);
      weights_.push_back(-0.25);
    }
    for (int k = 0; k < centre.mids; ++k) {
      vertices_.push_back(nodes_[centre.mid[size_t(k)]]);
      weights_.push_back(centre.mid_weight);
    }
    if (!centre.on_face) return cells_.add_point(mesh_, vertices_, weights_);
    std::array<uint64_t, 8> key;
    std::copy_n(vertices_.begin(), 8, key.begin());
    std::sort(key.begin(), key.end());
    const auto [at, added] = face_centres_.try_emplace(key, 0);
    if (added) at->second = cells_.add_point(mesh_, vertices_, weights_);
    return at->second;
  }

  // The p^3 tets of the node lattice: an upright tet at each lattice point (i + j + k < p), the
  // octahedron above it (i + j + k < p - 1) as four tets around its shortest diagonal, and an
  // upside-down tet beyond that (i + j + k < p - 2).
  void split_lagrange_tet(uint64_t c, int p) {
    std::vector<uint32_t>& table = tetra_tables_[size_t(p)];
    if (table.empty()) table = tetra_node_table(p);
    const auto node = [&](int i, int j, int k) { return nodes_[table[size_t((i * (p + 1) + j) * (p + 1) + k)]]; };
    for (int i = 0; i < p; ++i)
      for (int j = 0; i + j < p; ++j)
        for (int k = 0; i + j + k < p; ++k) {
          cells_.add(kTet, std::array{node(i, j, k), node(i + 1, j, k), node(i, j + 1, k), node(i, j, k + 1)}, c);
          if (i + j + k < p - 1)
            add_octahedron(c, {node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k), node(i, j, k + 1),
                               node(i + 1, j, k + 1), node(i, j + 1, k + 1)});
          if (i + j + k < p - 2)
            cells_.add(kTet,
                       std::array{node(i + 1, j + 1, k), node(i, j + 1, k + 1), node(i + 1, j, k + 1),
                                  node(i + 1, j + 1, k + 1)},
                       c);
        }
  }

  // An octahedron with the nodes 4-9 of a tet10's (the midpoints of its edges 0-1, 1-2, 2-0, 0-3,
  // 1-3, 2-3) as four tets around its shortest diagonal (the best-shaped; any fills it).
  void add_octahedron(uint64_t c, const std::array<uint64_t, 6>& mid) {
    const auto at = [&](uint8_t local) { return mid[size_t(local - 4)]; };
    int best = 0;
    double best_length = INFINITY;
    for (int d = 0; d < 3; ++d) {
      const vec3d e = mesh_.points[at(kTet10Diagonal[d][1])] - mesh_.points[at(kTet10Diagonal[d][0])];
      if (dot(e, e) < best_length) best_length = dot(e, e), best = d;
    }
    for (const auto& tet : kTet10Octahedron[best])
      cells_.add(kTet, std::array{at(tet[0]), at(tet[1]), at(tet[2]), at(tet[3])}, c);
  }

  // The p^3 hexes of the node lattice (for p = 1, the cell itself).
  void split_lagrange_hex(uint64_t c, int p) {
    for (int k = 0; k < p; ++k)
      for (int j = 0; j < p; ++j)
        for (int i = 0; i < p; ++i) {
          std::array<uint64_t, 8> hex;
          for (int n = 0; n < 8; ++n)
            hex[size_t(n)] =
                nodes_[lagrange_hex_node(i + kHexCorner[n][0], j + kHexCorner[n][1], k + kHexCorner[n][2], p)];
          cells_.add(kHex, hex, c);
        }
  }

  void split_wedge18(uint64_t c) {
    for (int layer = 0; layer < 2; ++layer)
      for (const auto& triangle : kLayerTriangle) {
        uint8_t wedge[6];
        for (int n = 0; n < 3; ++n) {
          wedge[n] = kWedge18Layer[layer][triangle[n]];
          wedge[n + 3] = kWedge18Layer[layer + 1][triangle[n]];
        }
        add(kWedge, wedge, c);
      }
  }

  void split_pyramid14(uint64_t c) {
    for (const auto& pyramid : kPyramid14Pyramids) add(kPyramid, pyramid, c);
    for (const auto& tet : kPyramid14Tets) add(kTet, tet, c);
  }

  MeshData& mesh_;
  CellRebuild& cells_;
  std::vector<uint64_t> nodes_, vertices_;
  std::vector<double> weights_;
  std::map<std::array<uint64_t, 8>, uint64_t> face_centres_;               // by the face's sorted nodes
  std::array<std::vector<uint32_t>, kMaxLagrangeOrder + 1> tetra_tables_;  // tetra_node_table(p), once used
};

constexpr uint8_t kLagrangeTetra = uint8_t(QuadraticCell::lagrange_tet),
                  kLagrangeHex = uint8_t(QuadraticCell::lagrange_hex), kLagrangePyramid = 74;

bool is_lagrange(uint8_t type) { return type >= kLagrangeTetra && type <= kLagrangePyramid; }

// Whether the splitter takes cells of this type, once Lagrange cells have their fixed types.
bool split_here(uint8_t type) {
  return quadratic_node_count(type) > 0 || type == kLagrangeHex || type == kLagrangeTetra;
}

// Lagrange cells as the fixed types of their nodes (the order checked by vertex count).
void lagrange_to_fixed_types(MeshData& m, const std::string& file) {
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    if (!is_lagrange(m.cell_types[c])) continue;
    const uint64_t nodes = m.cell_offsets[c + 1] - m.cell_offsets[c];
    const uint8_t fixed = lagrange_as_fixed_type(m.cell_types[c], nodes);
    if (fixed == 0)
      input_error(file, "cell " + std::to_string(c) + " (" + cell_type_name(m.cell_types[c]) + ") has " +
                            std::to_string(nodes) +
                            " nodes: volstream reads Lagrange hexahedra and tetra of order 1 to " +
                            std::to_string(kMaxLagrangeOrder) +
                            " ((p + 1)^3 and (p + 1)(p + 2)(p + 3) / 6 nodes), Lagrange wedges of order 1 and 2 (6 "
                            "and 18 nodes) and Lagrange pyramids of order 1 (5 nodes)");
    m.cell_types[c] = fixed;
  }
}

// The vertex counts of the cells the splitter takes (a Lagrange hexahedron's order was checked),
// and their vertex indices.
void check_quadratic_cells(const MeshData& m, const std::string& file) {
  for (uint64_t c = 0; c < m.cell_count(); ++c) {
    if (!split_here(m.cell_types[c])) continue;
    const int nodes = quadratic_node_count(m.cell_types[c]);
    const uint64_t begin = m.cell_offsets[c], count = m.cell_offsets[c + 1] - begin;
    if (nodes > 0 && count != uint64_t(nodes))
      input_error(file, "cell " + std::to_string(c) + " (" + cell_type_name(m.cell_types[c]) + ") has " +
                            std::to_string(count) + " vertices, expected " + std::to_string(nodes));
    for (uint64_t k = begin; k < begin + count; ++k)
      if (m.connectivity[k] >= m.points.size())
        input_error(file, "connectivity entry " + std::to_string(k) + " = " + std::to_string(m.connectivity[k]) +
                              " is out of range (" + std::to_string(m.points.size()) + " points)");
  }
}

}  // namespace

uint8_t lagrange_as_fixed_type(uint32_t vtk_type, uint64_t nodes) {
  struct Order {
    uint32_t lagrange;
    uint64_t nodes;
    uint8_t fixed;
  };
  constexpr Order kOrders[] = {
      {71, 4, kTet}, {72, 8, kHex}, {73, 6, kWedge}, {73, 18, uint8_t(QuadraticCell::wedge18)}, {74, 5, kPyramid}};
  for (const Order& o : kOrders)
    if (o.lagrange == vtk_type && o.nodes == nodes) return o.fixed;
  if (vtk_type == kLagrangeHex && lagrange_hex_order(nodes) >= 2) return kLagrangeHex;
  if (vtk_type == kLagrangeTetra && lagrange_tet_order(nodes) >= 2) return kLagrangeTetra;
  return 0;
}

void lagrange_hexahedra_from_pre_vtk91_order(MeshData& m) {
  for (uint64_t c = 0; c < m.cell_count() && c + 1 < m.cell_offsets.size(); ++c) {
    const uint64_t begin = m.cell_offsets[c], end = m.cell_offsets[c + 1];
    const int p = m.cell_types[c] == kLagrangeHex && begin <= end ? lagrange_hex_order(end - begin) : 0;
    if (p < 2 || end > m.connectivity.size()) continue;
    // edges 10 and 11 (2-6 and 3-7), p - 1 nodes each, after the corners and edges 0-9
    const auto edge10 = m.connectivity.begin() + int64_t(begin + 8 + 10 * uint64_t(p - 1));
    std::swap_ranges(edge10, edge10 + (p - 1), edge10 + (p - 1));
  }
}

int quadratic_node_count(uint32_t vtk_type) {
  switch (vtk_type) {
    case uint32_t(QuadraticCell::tet10):
      return 10;
    case uint32_t(QuadraticCell::hex20):
      return 20;
    case uint32_t(QuadraticCell::wedge15):
      return 15;
    case uint32_t(QuadraticCell::pyramid13):
      return 13;
    case uint32_t(QuadraticCell::hex27):
      return 27;
    case uint32_t(QuadraticCell::wedge18):
      return 18;
    case uint32_t(QuadraticCell::hex24):
      return 24;
    default:
      return 0;
  }
}

void split_quadratic_cells(MeshData& m, const std::string& file, SplitMemo* memo) {
  if (std::none_of(m.cell_types.begin(), m.cell_types.end(), [](uint8_t t) { return split_here(t) || is_lagrange(t); }))
    return;
  if (memo && memo->reuse(m, {}, file)) return;
  check_rebuild_input(m, "quadratic cells", file);
  if (memo) memo->split_begins(m, {});
  lagrange_to_fixed_types(m, file);
  check_quadratic_cells(m, file);
  CellRebuild cells;
  QuadraticSplitter splitter(m, cells);
  for (uint64_t c = 0; c < m.cell_count(); ++c)
    if (split_here(m.cell_types[c]))
      splitter.split(c);
    else
      cells.keep(m, c);
  if (!memo) return std::move(cells).finish(m);
  cells.finish(m);
  memo->split_ends(std::move(cells), m.points);
}

}  // namespace vs
