// The procedural demos. One octree driver (survey, replay) serves both; each demo only says
// where to refine and what its fields are.
//
// Memory: the source never holds the cells. It records the octree's refinement decisions as one bit
// per node above level 0 (well under a byte per cell) and replays them to produce the cells
// (take_cells) or the values in the same order (read_values). So the only big allocation is the
// caller's: 16 bytes per cell for the cell list, 4 per value.
#include "volstream/amr/demo.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <utility>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"

namespace vs {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kDemoLevels = 6;  // both demos: level 0 (finest) .. 5 (root cells)

double sqr(double x) { return x * x; }
double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// SplitMix64: a tiny generator whose output is fixed by its definition (the standard library's
// distributions are not), so the demos are the same everywhere.
class SplitMix {
 public:
  explicit SplitMix(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform(double lo = 0, double hi = 1) { return lo + (hi - lo) * double(next() >> 11) * 0x1.0p-53; }
  double log_uniform(double lo, double hi) { return lo * std::pow(hi / lo, uniform()); }

 private:
  uint64_t state_;
};

// =================================================================================================
// The demo interface: where to refine and what the fields are.
// =================================================================================================

// An octree node as the refinement criteria see it: a cube in world coordinates.
struct Node {
  vec3d center;
  double half;  // half the node's width
  int level;
  double width() const { return 2 * half; }
  // Centre to corner: every point of the node is within this distance of its centre, so a
  // distance shortened by it bounds the distance from the whole node.
  double reach() const { return half * 1.7320508075688772; }
};

// Evaluates one field at one step at world positions.
using FieldFunction = std::function<float(const vec3d&)>;

class DemoModel {
 public:
  virtual ~DemoModel() = default;
  virtual std::string name() const = 0;
  virtual vec3d domain_center() const = 0;
  virtual vec3d domain_extent() const = 0;      // nominal; the root grid rounds it up to whole root cells
  virtual double trial_root_width() const = 0;  // gives a few 10^4 cells: the size search starts here
  virtual double max_root_width() const = 0;    // the coarsest root grid the size search may use
  // Split this node (level > 0) into 8 children? Must depend only on the node.
  virtual bool refine(const Node& node) const = 0;
  virtual std::vector<std::string> field_names() const = 0;
  virtual double step_time(int step) const = 0;
  virtual FieldFunction field(int field, int step) const = 0;
};

// =================================================================================================
// Octree driver, shared by both demos.
//
// The root grid is split into rows of root cells (fixed y and z); each row's leaves come out in a
// fixed depth-first order, and rows are concatenated in order, so the cell order depends on nothing
// but the refinement decisions. Rows are the unit of parallel work.
// =================================================================================================

struct RootGrid {
  vec3i dims;         // root cells per axis
  int levels = 0;     // root cells have level levels-1
  vec3d origin;       // world position of grid point (0,0,0)
  double finest = 0;  // world width of one grid unit (a level-0 cell)

  int64_t rows() const { return int64_t(dims.y) * dims.z; }
  Node node(const Cell& c) const {
    const int32_t w = level_width(c.level);
    return {origin + (vec3d(c.lower) + vec3d(0.5 * w)) * finest, 0.5 * w * finest, c.level};
  }
};

// The root grid for a given root cell width: the nominal domain rounded up to whole root cells
// (so the domain always contains the nominal one), centred on it.
RootGrid make_root_grid(const DemoModel& m, double root_width) {
  RootGrid g;
  g.levels = kDemoLevels;
  const vec3d extent = m.domain_extent();
  for (int a = 0; a < 3; ++a) g.dims[a] = std::max(1, int(std::ceil(extent[a] / root_width - 1e-6)));
  g.origin = m.domain_center() - vec3d(g.dims) * (0.5 * root_width);
  g.finest = root_width / level_width(g.levels - 1);
  return g;
}

// Visits the leaves below `c` depth-first (children x fastest). split(cell) decides for cells above
// level 0; leaf(cell) receives the leaves.
template <typename Split, typename Leaf>
void walk(const Cell& c, Split& split, Leaf& leaf) {
  if (c.level == 0 || !split(c)) return leaf(c);
  const int32_t h = level_width(c.level - 1);
  for (int k = 0; k < 8; ++k) {
    const Cell child{c.lower + vec3i(k & 1 ? h : 0, k & 2 ? h : 0, k & 4 ? h : 0), c.level - 1};
    walk(child, split, leaf);
  }
}

template <typename Split, typename Leaf>
void walk_row(const RootGrid& g, int64_t row, Split& split, Leaf& leaf) {
  const int32_t y = int32_t(row % g.dims.y), z = int32_t(row / g.dims.y), w = level_width(g.levels - 1);
  for (int32_t x = 0; x < g.dims.x; ++x) walk(Cell{vec3i(x, y, z) * w, g.levels - 1}, split, leaf);
}

// The octree as recorded by one pass of the refinement criteria: per row of root cells, its
// decisions as bits (1 = split; nodes at level 0 have none) and its leaf count. Replaying the bits
// gives the cells, so this is all the source keeps: well under a byte per cell.
struct OctreeShape {
  RootGrid grid;
  double root_width = 0;
  std::vector<std::vector<uint64_t>> row_bits;
  std::vector<uint64_t> row_cell;  // first cell of each row, plus the total at the end
  uint64_t cell_count() const { return row_cell.back(); }
};

// Runs the criteria over every node, rows in parallel.
OctreeShape survey(const DemoModel& m, double root_width) {
  OctreeShape s;
  s.root_width = root_width;
  s.grid = make_root_grid(m, root_width);
  const RootGrid& g = s.grid;
  const size_t rows = size_t(g.rows());
  s.row_bits.resize(rows);
  s.row_cell.assign(rows + 1, 0);
  parallel_for_ranges(g.rows(), [&](int64_t begin, int64_t end) {
    for (int64_t row = begin; row < end; ++row) {
      std::vector<uint64_t>& bits = s.row_bits[size_t(row)];
      uint64_t decisions = 0, leaves = 0;
      auto split = [&](const Cell& cell) {
        const bool yes = m.refine(g.node(cell));
        if (decisions % 64 == 0) bits.push_back(0);
        bits.back() |= uint64_t(yes) << (decisions % 64);
        ++decisions;
        return yes;
      };
      auto leaf = [&](const Cell&) { ++leaves; };
      walk_row(g, row, split, leaf);
      s.row_cell[size_t(row) + 1] = leaves;  // a count for now, turned into offsets below
    }
  });
  for (size_t r = 0; r < rows; ++r) s.row_cell[r + 1] += s.row_cell[r];
  return s;
}

// Replays the recorded octree: visit(index, cell) for every leaf, index in cell order. Parallel.
template <typename Visit>
void for_each_leaf(const OctreeShape& s, Visit&& visit) {
  parallel_for_ranges(s.grid.rows(), [&](int64_t begin, int64_t end) {
    for (int64_t row = begin; row < end; ++row) {
      const uint64_t* bits = s.row_bits[size_t(row)].data();
      uint64_t i = 0, index = s.row_cell[size_t(row)];
      auto split = [&](const Cell&) {
        const bool yes = (bits[i / 64] >> (i % 64)) & 1;
        ++i;
        return yes;
      };
      auto leaf = [&](const Cell& c) { visit(index++, c); };
      walk_row(s.grid, row, split, leaf);
    }
  });
}

// -------------------------------------------------------------------------------------------------
// Size search: the root cell width is the one continuous knob (finer roots scale every refined
// region with them). Counts follow roughly a power law in it (surfaces ~ width^-2, volumes
// ~ width^-3), so each pass extrapolates in log-log space from the last two counts. The pass that
// lands closest is kept as the result, so the criteria run once more than the passes, no more.
// -------------------------------------------------------------------------------------------------

OctreeShape fit_cell_count(const DemoModel& m, uint64_t target) {
  constexpr double kTolerance = 0.1;  // stop within 10% of the target
  constexpr int kMaxPasses = 10;
  // A pass may multiply the count by at most this, which bounds the cost of a bad guess; the first
  // pass only calibrates the exponent near the cheap trial size.
  constexpr double kFirstGrowth = 4, kMaxGrowth = 16;
  const double min_width = reduce_max(m.domain_extent()) * level_width(kDemoLevels - 1) / (kMaxCoord / 2);
  auto miss = [&](const OctreeShape& s) { return std::abs(std::log(double(s.cell_count()) / double(target))); };

  OctreeShape best = survey(m, m.trial_root_width());
  double width = best.root_width, total = double(best.cell_count()), exponent = 2.5;
  for (int pass = 1; pass < kMaxPasses && miss(best) > std::log1p(kTolerance); ++pass) {
    const double limit = pass == 1 ? kFirstGrowth : kMaxGrowth;
    const double growth = std::clamp(double(target) / total, 1 / limit, limit);
    const double next_width = std::clamp(width * std::pow(growth, -1 / exponent), min_width, m.max_root_width());
    if (next_width == width) break;  // pinned at a bound
    OctreeShape next = survey(m, next_width);
    const double next_total = double(next.cell_count());
    const double slope = std::log(next_total / total) / std::log(width / next_width);
    if (std::isfinite(slope) && slope > 0) exponent = std::clamp(slope, 1.5, 3.5);
    width = next_width;
    total = next_total;
    if (miss(next) < miss(best)) best = std::move(next);
  }
  return best;
}

// =================================================================================================
// jet: an aircraft-like body in a uniform stream along +x (SI units, metres).
// The flow is a sum of analytic parts: a Rankine body (source + sink) for the fuselage, a swept
// lifting line for the wing, two trailing wingtip vortices that meander (a Crow-like instability
// travelling downstream) and a von Karman street shed from the tail at a Strouhal frequency. All
// vortices use the Kaufmann-Scully core (speed G/2pi * r/(rc^2 + r^2)): smooth, and no exp per cell.
// =================================================================================================
namespace jet {

constexpr double kSpeed = 50;           // free stream, m/s
constexpr double kAir = 1.2;            // air density, kg/m^3
constexpr double kStepSeconds = 0.025;  // an eighth of the shedding period per step

// The body: a fuselage of two round cones (cylindrical cabin, upswept tail cone) and three thin
// lifting surfaces (rounded boxes, tapered and swept). Exact distance functions keep the
// refinement band the same width everywhere; the taper and sweep distort them by a few percent.
struct Fuselage {
  vec3d a, b;
  double ra, rb;
};
constexpr Fuselage kFuselage[] = {
    {{-5.9, 0, 0}, {3, 0, 0}, 1.1, 1.1},   // cabin, nose at x = -7
    {{3, 0, 0}, {7.2, 0, 0.5}, 1.1, 0.3},  // tail cone
};
struct Surface {
  vec3d center, half;       // half extents before rounding: chord/2, span/2, thickness/2
  double round;             // rounding radius (leading and trailing edges, tips)
  double taper;             // the chord shrinks by this fraction towards the tips
  double sweep_y, sweep_z;  // x shifted back by sweep_y * |y| (wings) and sweep_z * z (fin)
};
constexpr Surface kSurfaces[] = {
    {{-0.8, 0, -0.35}, {1.5, 7.3, 0.01}, 0.15, 0.5, 0.3, 0},  // wing, tips at y = +-7.45
    {{5.9, 0, 0.5}, {0.7, 2.9, 0.01}, 0.08, 0.4, 0.35, 0},    // tailplane
    {{5.6, 0, 1.9}, {0.8, 0.01, 1.3}, 0.08, 0.0, 0, 0.5},     // fin
};

// Lifting line and tip vortices.
constexpr double kCirculation = 120;                        // m^2/s: lift = rho U Gamma span, about 100 kN
constexpr double kTipX = 1.8, kTipY = 7.3, kWingZ = -0.35;  // trailing edge at the right tip
constexpr double kTipCore2 = 0.04;                          // initial core radius^2 (0.2 m)
constexpr double kEddyViscosity = 0.05;                     // m^2/s, grows the tip cores downstream
constexpr double kMeanderWavenumber = 2 * kPi / 10;

// Fuselage as a Rankine body: a source at the nose and a sink at the tail (strength U pi R^2).
constexpr double kSourceX = 6.2, kSourceStrength = kSpeed * kPi * 1.1 * 1.1, kSourceSoftening2 = 0.5;

// Von Karman street behind the tail: Strouhal 0.2 on the 2.2 m fuselage, so about 5 Hz.
constexpr double kShedX = 7.6, kShedHalfPeriod = 0.1, kConvection = 42;
constexpr double kStreetCirculation = 100, kStreetCore2 = 0.35 * 0.35, kStreetViscosity = 0.3;
constexpr double kStreetOffset = 1.2;  // +-y of the two rows (Karman's ratio 0.28 of the spacing)
constexpr double kStreetDecay = 0.8;   // seconds
constexpr double kStreetEnd = 40;      // x beyond every domain size: vortices past it are dropped

// Refinement: the surface band (in node widths beyond the node's own reach) and the wake levels.
constexpr double kBand = 1.0;
constexpr int kInnerWakeLevel = 3, kOuterWakeLevel = 4;

// Exact signed distance to a cone with spherical caps: radius ra at a, rb at b (after Quilez).
double round_cone_distance(const vec3d& p, const Fuselage& f) {
  auto sign = [](double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); };
  const vec3d ba = f.b - f.a, pa = p - f.a;
  const double l2 = dot(ba, ba), rr = f.ra - f.rb, a2 = l2 - rr * rr, il2 = 1 / l2;
  const double y = dot(pa, ba), z = y - l2;
  const vec3d xv = pa * l2 - ba * y;
  const double x2 = dot(xv, xv), y2 = y * y * l2, z2 = z * z * l2, k = sign(rr) * rr * rr * x2;
  if (sign(z) * a2 * z2 > k) return std::sqrt(x2 + z2) * il2 - f.rb;
  if (sign(y) * a2 * y2 < k) return std::sqrt(x2 + y2) * il2 - f.ra;
  return (std::sqrt(x2 * a2 * il2) + y * rr) * il2 - f.ra;
}

double surface_distance(const vec3d& p, const Surface& s) {
  vec3d q = p - s.center;
  q.x -= s.sweep_y * std::abs(q.y) + s.sweep_z * q.z;
  vec3d half = s.half;
  half.x *= 1 - s.taper * std::min(1.0, std::abs(q.y) / s.half.y);
  const vec3d d = vec3d(std::abs(q.x), std::abs(q.y), std::abs(q.z)) - half;  // rounded box
  return length(vmax(d, vec3d(0))) + std::min(reduce_max(d), 0.0) - s.round;
}

double body_distance(const vec3d& p) {
  double d = INFINITY;
  for (const Fuselage& f : kFuselage) d = std::min(d, round_cone_distance(p, f));
  for (const Surface& s : kSurfaces) d = std::min(d, surface_distance(p, s));
  return d;
}

// The right tip vortex's centre line (the left one mirrors it in y) at x, for time t.
struct TipLine {
  double y, z, core2, strength;  // strength: 0 ahead of the wingtip, ramping to 1 behind it
};
double tip_meander_amplitude(double x) { return 0.04 * std::max(0.0, x - kTipX); }
double tip_mean_y(double x) { return 5.9 + 1.4 * std::exp(-std::max(0.0, x - kTipX) / 4); }  // rolls up inboard
double tip_mean_z(double x) { return kWingZ - 0.03 * std::max(0.0, x - kTipX); }             // the pair descends
TipLine tip_line(double x, double t) {
  const double strength = smoothstep((x - kTipX + 1) / 2);
  if (strength == 0) return {0, 0, 1, 0};
  const double s = std::max(0.0, x - kTipX), a = tip_meander_amplitude(x);
  const double phase = kMeanderWavenumber * (x - kSpeed * t);
  return {tip_mean_y(x) + a * std::sin(phase), tip_mean_z(x) + 0.6 * a * std::cos(phase),
          kTipCore2 + 4 * kEddyViscosity * s / kSpeed, strength};
}

double street_half_height(double x) { return 1.3 + 0.08 * std::max(0.0, x - kShedX); }

struct StreetVortex {
  double x, y, gamma, core2, inv_half_height;
};

// The vortices of the street alive at time t: vortex n is shed at n * half period, alternately
// from the upper (clockwise) and lower side, then drifts downstream, spreads and decays.
std::vector<StreetVortex> street_at(double t) {
  std::vector<StreetVortex> street;
  const double max_age = (kStreetEnd - kShedX) / kConvection;
  for (int64_t n = int64_t(std::ceil((t - max_age) / kShedHalfPeriod)); double(n) * kShedHalfPeriod <= t; ++n) {
    const double age = t - double(n) * kShedHalfPeriod, side = (n % 2 == 0) ? 1 : -1;
    const double x = kShedX + kConvection * age;
    const double gamma = -side * kStreetCirculation * smoothstep(age / kShedHalfPeriod) * std::exp(-age / kStreetDecay);
    street.push_back({x, side * kStreetOffset * (1 + 0.3 * age), gamma, kStreetCore2 + 4 * kStreetViscosity * age,
                      1 / street_half_height(x)});
  }
  return street;
}

// Velocity, vorticity and core pressure of one 2-D Scully vortex at offset (a, b) from its axis,
// scaled by `weight` (its strength envelope along the axis).
struct Swirl {
  double va = 0, vb = 0, vorticity = 0, pressure = 0;
};
Swirl scully(double a, double b, double gamma, double core2, double weight) {
  const double inv = 1 / (core2 + a * a + b * b), g = gamma * weight, speed = g / (2 * kPi) * inv;
  return {-speed * b, speed * a, g / kPi * core2 * inv * inv, -kAir * g * g / (8 * kPi * kPi) * inv};
}

struct VortexSum {
  vec3d velocity, vorticity;
  double pressure = 0;
};

// All wake vortices (tips and street) at p.
VortexSum wake_vortices(const vec3d& p, double t, const std::vector<StreetVortex>& street) {
  VortexSum sum;
  const TipLine tip = tip_line(p.x, t);
  if (tip.strength > 0) {
    for (double side : {1.0, -1.0}) {  // right tip: vorticity +x (upwash outboard); left mirrors
      const Swirl s = scully(p.y - side * tip.y, p.z - tip.z, side * kCirculation, tip.core2, tip.strength);
      sum.velocity = sum.velocity + vec3d(0, s.va, s.vb);
      sum.vorticity.x += side * s.vorticity;
      sum.pressure += s.pressure;
    }
  }
  for (const StreetVortex& v : street) {
    const double envelope = 1 / (1 + sqr(sqr(p.z * v.inv_half_height)));  // finite span in z
    const Swirl s = scully(p.x - v.x, p.y - v.y, v.gamma, v.core2, envelope);
    sum.velocity = sum.velocity + vec3d(s.va, s.vb, 0);
    sum.vorticity.z += (v.gamma > 0 ? 1 : -1) * s.vorticity;
    sum.pressure += s.pressure;
  }
  return sum;
}

vec3d point_source(const vec3d& p, const vec3d& at, double strength) {
  const vec3d d = p - at;
  const double r2 = dot(d, d) + kSourceSoftening2;
  return d * (strength / (4 * kPi * r2 * std::sqrt(r2)));
}

// Biot-Savart velocity of a straight vortex segment a -> b with a smoothed core.
vec3d vortex_segment(const vec3d& p, const vec3d& a, const vec3d& b, double gamma) {
  const vec3d r1 = p - a, r2 = p - b, r0 = b - a, c = cross(r1, r2);
  const double denominator = dot(c, c) + 0.09 * dot(r0, r0);  // core 0.3 m
  const double along = dot(r0, r1 / length(r1) - r2 / length(r2));
  return c * (gamma / (4 * kPi) * along / denominator);
}

// The irrotational part: free stream, Rankine fuselage and the wing's swept bound vortex.
vec3d potential_velocity(const vec3d& p) {
  const vec3d left{1.0, -kTipY, kWingZ}, root{-1.55, 0, kWingZ}, right{1.0, kTipY, kWingZ};  // quarter-chord line
  return vec3d(kSpeed, 0, 0) + point_source(p, {-kSourceX, 0, 0}, kSourceStrength) +
         point_source(p, {kSourceX, 0, 0}, -kSourceStrength) + vortex_segment(p, left, root, kCirculation) +
         vortex_segment(p, root, right, kCirculation);
}

// Vorticity of the body's boundary layer: U/delta, decaying over a thickness that grows from the nose.
double boundary_layer_vorticity(const vec3d& p) {
  const double delta = 0.03 + 0.01 * std::clamp(p.x + 7, 0.0, 20.0);
  return kSpeed / delta * std::exp(-std::abs(body_distance(p)) / delta);
}

// Does the node touch the inner wake (tubes around the tip vortices' paths, the street's slab)?
bool touches_inner_wake(const Node& n) {
  const vec3d c = n.center;
  const double r = n.reach(), x = c.x + r;
  if (x > kTipX - 1) {
    const double tube = 1.2 + tip_meander_amplitude(x) + r;
    if (sqr(std::abs(c.y) - tip_mean_y(c.x)) + sqr(c.z - tip_mean_z(c.x)) < sqr(tube)) return true;
  }
  return x > kShedX - 1 && std::abs(c.y) < 2.4 + 0.08 * std::max(0.0, x - kShedX) + r &&
         std::abs(c.z) < 1.5 * street_half_height(x) + r;
}
// ... or the outer wake (a widening slab behind the wing that holds all of it)?
bool touches_outer_wake(const Node& n) {
  const vec3d c = n.center;
  const double r = n.reach(), spread = 0.1 * std::max(0.0, c.x + r + 3);
  return c.x + r > -3 && std::abs(c.y) < 9.5 + spread + r && std::abs(c.z) < 2.5 + spread + r;
}

class JetModel final : public DemoModel {
 public:
  std::string name() const override { return "jet"; }
  vec3d domain_center() const override { return {8, 0, 0}; }
  vec3d domain_extent() const override { return {40, 20, 20}; }
  double trial_root_width() const override { return 6.67; }
  double max_root_width() const override { return 20; }

  bool refine(const Node& n) const override {
    // Surface band: the body's surface passes within kBand node widths of the node.
    if (std::abs(body_distance(n.center)) < n.reach() + kBand * n.width()) return true;
    // Wake: split while the children are coarser than the level the wake wants there.
    if (n.level > kInnerWakeLevel && touches_inner_wake(n)) return true;
    return n.level > kOuterWakeLevel && touches_outer_wake(n);
  }

  std::vector<std::string> field_names() const override { return {"pressure", "velocity", "vorticity"}; }
  double step_time(int step) const override { return step * kStepSeconds; }

  FieldFunction field(int field, int step) const override {
    const double t = step_time(step);
    auto street = std::make_shared<const std::vector<StreetVortex>>(street_at(t));
    switch (field) {
      case 0:  // gauge pressure: Bernoulli on the irrotational part plus the vortex cores' suction
        return [t, street](const vec3d& p) {
          const vec3d u = potential_velocity(p);
          return float(0.5 * kAir * (kSpeed * kSpeed - dot(u, u)) + wake_vortices(p, t, *street).pressure);
        };
      case 1:
        return [t, street](const vec3d& p) {
          return float(length(potential_velocity(p) + wake_vortices(p, t, *street).velocity));
        };
      default:
        return [t, street](const vec3d& p) {
          return float(length(wake_vortices(p, t, *street).vorticity) + boundary_layer_vorticity(p));
        };
    }
  }
};

}  // namespace jet

// =================================================================================================
// cosmo: a 32 Mpc box (units: Mpc, density relative to the mean). Clumps with cored r^-3 profiles
// collapse over the steps (central density up 20x at fixed outer profile), joined by filaments, on a
// log-normal-like background whose contrast grows. Refinement as in Enzo: a node is split where
// the mass in it exceeds a fixed mass, i.e. density > threshold * 8^(levels below the root).
// Profiles are cut off smoothly at a finite radius so that voids stay empty (1e-3) and distant
// clumps can be skipped exactly.
// =================================================================================================
namespace cosmo {

constexpr double kBox = 32;
constexpr int kClumps = 12;
constexpr double kOverdensityAtRadius = 50;  // clump density at its virial radius
constexpr double kCutoffRadii = 5;           // profiles vanish at this many virial radii
constexpr double kCollapse = 20;             // central density grows by this over the steps
constexpr double kFilamentRadius = 1.0;      // Mpc, where the filament profile reaches zero
constexpr double kMassThreshold = 4;         // refine where mass > 4 mean root cells' mass
constexpr double kTemperatureFloor = 100;    // K, cold cores

struct Clump {
  vec3d center;
  double radius, final_central_density;
};
struct Filament {
  vec3d a, b;
  double amplitude;
};

// A clump at one moment: profile mass / (core2 + r^2)^1.5 inside its cutoff, windowed to zero there.
struct ClumpState {
  vec3d center;
  double mass, core2, cutoff, cutoff2, virial_temperature, shock_radius, cooling2;
};
struct FilamentState {
  vec3d a, ab;  // from a to a + ab
  double inv_length2, amplitude;
};
struct Universe {  // everything that depends on time, at one step
  std::vector<ClumpState> clumps;
  std::vector<FilamentState> filaments;
  double background_offset, background_contrast;  // log10 density = offset + contrast * g(x)
};

struct Wave {
  vec3d k;
  double phase;
};

double window(double r2, double cutoff2) { return r2 < cutoff2 ? sqr(1 - r2 / cutoff2) : 0; }
FilamentState filament_state(const Filament& f, double growth) {
  const vec3d ab = f.b - f.a;
  return {f.a, ab, 1 / dot(ab, ab), f.amplitude * growth};
}
double segment_distance2(const vec3d& p, const FilamentState& f) {
  const double s = std::clamp(dot(p - f.a, f.ab) * f.inv_length2, 0.0, 1.0);
  const vec3d e = p - (f.a + f.ab * s);
  return dot(e, e);
}
double filament_kernel(double d2) {
  const double x = 1 - d2 / sqr(kFilamentRadius);
  return x > 0 ? x * x * x : 0;
}

// Which clumps and filaments can reach each bin of a coarse grid over the box (their profiles
// vanish beyond a finite radius), so that a point visits only those listed for its bin. A point
// outside the box, or asking for more distance slack than the lists allow for, visits all.
struct Nearby {
  std::vector<uint16_t> clumps, filaments;
};
class NeighbourBins {
 public:
  static constexpr int kBins = 16;
  static constexpr double kBinWidth = kBox / kBins, kMargin = 1.0;  // Mpc of slack allowed for

  NeighbourBins(const std::vector<Clump>& clumps, const std::vector<Filament>& filaments)
      : all_(within(vec3d(0), INFINITY, clumps, filaments)) {
    const double reach = kMargin + 0.5 * std::sqrt(3.0) * kBinWidth;  // margin plus the bin's half diagonal
    for (int b = 0; b < kBins * kBins * kBins; ++b) {
      const vec3d center = (vec3d(b % kBins, b / kBins % kBins, b / (kBins * kBins)) + vec3d(0.5)) * kBinWidth;
      bins_.push_back(within(center, reach, clumps, filaments));
    }
  }
  const Nearby& at(const vec3d& p, double slack) const {
    const vec3d q = p / kBinWidth;
    if (slack > kMargin || reduce_min(q) < 0 || reduce_max(q) >= kBins) return all_;
    return bins_[size_t(int(q.x) + kBins * (int(q.y) + kBins * int(q.z)))];
  }

 private:
  // The clumps and filaments whose profiles reach within `reach` of p.
  static Nearby within(const vec3d& p, double reach, const std::vector<Clump>& clumps,
                       const std::vector<Filament>& filaments) {
    Nearby n;
    for (size_t i = 0; i < clumps.size(); ++i)
      if (length(p - clumps[i].center) < kCutoffRadii * clumps[i].radius + reach) n.clumps.push_back(uint16_t(i));
    for (size_t i = 0; i < filaments.size(); ++i)
      if (std::sqrt(segment_distance2(p, filament_state(filaments[i], 1))) < kFilamentRadius + reach)
        n.filaments.push_back(uint16_t(i));
    return n;
  }

  Nearby all_;
  std::vector<Nearby> bins_;
};

class CosmoModel final : public DemoModel {
 public:
  explicit CosmoModel(int steps) : steps_(steps) {
    SplitMix rng(0xC05A0);
    place_clumps(rng);
    connect_filaments(rng);
    const vec3d directions[3] = {{1, 0.3, 0.2}, {-0.2, 1, 0.4}, {0.3, -0.5, 1}};
    const double wavelengths[3] = {17, 13, 11};
    for (int i = 0; i < 3; ++i)
      waves_[i] = {normalize(directions[i]) * (2 * kPi / wavelengths[i]), rng.uniform(0, 2 * kPi)};
    final_ = universe_at(1);
    max_background_ = background_from_g(1, final_);
    bins_ = std::make_unique<NeighbourBins>(clumps_, filaments_);
  }

  std::string name() const override { return "cosmo"; }
  vec3d domain_center() const override { return vec3d(kBox / 2); }
  vec3d domain_extent() const override { return vec3d(kBox); }
  double trial_root_width() const override { return 2; }
  double max_root_width() const override { return kBox / 2; }

  // The topology serves every step, so it refines for the final, most collapsed state (each
  // profile only steepens over time). The node's largest density is bounded by shortening every
  // distance by the node's reach; the smooth background counts in full only at the root level.
  bool refine(const Node& n) const override {
    const int depth = kDemoLevels - 1 - n.level;
    const double threshold = kMassThreshold * double(uint64_t(1) << (3 * depth));
    const double background = depth == 0 ? background_density(n.center, final_) : max_background_;
    return background + matter(n.center, final_, n.reach()) > threshold;
  }

  std::vector<std::string> field_names() const override { return {"density", "temperature"}; }
  double step_time(int step) const override { return 2 + 11.8 * progress(step); }  // cosmic time, Gyr

  FieldFunction field(int field, int step) const override {
    auto u = std::make_shared<const Universe>(universe_at(progress(step)));
    if (field == 0) return [this, u](const vec3d& p) { return float(background_density(p, *u) + matter(p, *u, 0)); };
    return [this, u](const vec3d& p) { return float(temperature(p, *u)); };
  }

 private:
  // 0 at the first step, 1 at the last (a single step shows the final state).
  double progress(int step) const { return steps_ > 1 ? double(step) / (steps_ - 1) : 1.0; }

  void place_clumps(SplitMix& rng) {
    while (clumps_.size() < size_t(kClumps)) {
      const vec3d c(rng.uniform(3, kBox - 3), rng.uniform(3, kBox - 3), rng.uniform(3, kBox - 3));
      bool apart = true;
      for (const Clump& o : clumps_) apart = apart && length(o.center - c) > 6;
      const double radius = rng.log_uniform(0.8, 1.8), central = rng.log_uniform(1e5, 1e6);
      if (apart) clumps_.push_back({c, radius, central});
    }
  }

  // Each clump to its two nearest neighbours (each pair once), like the cosmic web's filaments.
  void connect_filaments(SplitMix& rng) {
    std::vector<std::pair<int, int>> pairs;
    for (int i = 0; i < kClumps; ++i) {
      auto distance = [&](int j) { return length(clumps_[size_t(j)].center - clumps_[size_t(i)].center); };
      std::vector<int> others;
      for (int j = 0; j < kClumps; ++j)
        if (j != i) others.push_back(j);
      std::partial_sort(others.begin(), others.begin() + 2, others.end(),
                        [&](int a, int b) { return distance(a) < distance(b); });
      for (int k = 0; k < 2; ++k) {
        const std::pair<int, int> pair(std::min(i, others[size_t(k)]), std::max(i, others[size_t(k)]));
        if (std::find(pairs.begin(), pairs.end(), pair) == pairs.end()) pairs.push_back(pair);
      }
    }
    for (const auto& [i, j] : pairs)
      filaments_.push_back({clumps_[size_t(i)].center, clumps_[size_t(j)].center, rng.uniform(12, 30)});
  }

  // The state at progress u in [0, 1]: cores collapse (central density up kCollapse times while the
  // outer profile stays), shocks expand, filaments and the background's contrast grow.
  Universe universe_at(double u) const {
    Universe w;
    w.background_offset = -1.2 - 0.2 * u;
    w.background_contrast = 1.8 + 0.4 * u;
    for (const Clump& c : clumps_) {
      const double central = c.final_central_density / std::pow(kCollapse, 1 - u);
      const double mass = kOverdensityAtRadius * std::pow(c.radius, 3);  // the r^-3 tail's amplitude
      const double core2 = sqr(std::cbrt(mass / central));
      const double cutoff = kCutoffRadii * c.radius;
      w.clumps.push_back({.center = c.center,
                          .mass = mass,
                          .core2 = core2,
                          .cutoff = cutoff,
                          .cutoff2 = cutoff * cutoff,
                          .virial_temperature = 1e7 * sqr(c.radius / 1.8),  // T ~ M^(2/3) ~ R^2
                          .shock_radius = c.radius * (0.6 + 0.8 * u),
                          .cooling2 = 9 * core2});
    }
    for (const Filament& f : filaments_) w.filaments.push_back(filament_state(f, 0.5 + 0.5 * u));
    return w;
  }

  // The background: three plane waves averaged (g in [-1, 1]) through an exponential.
  double background_g(const vec3d& p) const {
    double g = 0;
    for (const Wave& w : waves_) g += std::sin(dot(w.k, p) + w.phase);
    return g / 3;
  }
  static double background_from_g(double g, const Universe& w) {
    return std::exp(2.302585092994046 * (w.background_offset + w.background_contrast * g));  // 10^(...)
  }
  double background_density(const vec3d& p, const Universe& w) const { return background_from_g(background_g(p), w); }

  // Clumps and filaments at p, with every distance shortened by `slack` (0: the exact density).
  double matter(const vec3d& p, const Universe& w, double slack) const {
    const Nearby& near = bins_->at(p, slack);
    double rho = 0;
    for (uint16_t i : near.clumps) {
      const ClumpState& c = w.clumps[i];
      double r2 = dot(p - c.center, p - c.center);
      if (r2 >= sqr(c.cutoff + slack)) continue;
      if (slack > 0) r2 = sqr(std::max(0.0, std::sqrt(r2) - slack));
      const double q = c.core2 + r2;
      rho += c.mass / (q * std::sqrt(q)) * window(r2, c.cutoff2);
    }
    for (uint16_t i : near.filaments) {
      const FilamentState& f = w.filaments[i];
      double d2 = segment_distance2(p, f);
      if (d2 >= sqr(kFilamentRadius + slack)) continue;
      if (slack > 0) d2 = sqr(std::max(0.0, std::sqrt(d2) - slack));
      rho += f.amplitude * filament_kernel(d2);
    }
    return rho;
  }

  // Warm photo-heated gas in the background, shock-heated halos (virial temperature inside an
  // expanding shock) and warm-hot filaments, all cooling to kTemperatureFloor in the dense cores.
  double temperature(const vec3d& p, const Universe& w) const {
    const Nearby& near = bins_->at(p, 0);
    double heat = 2e4 * std::sqrt(background_density(p, w)), cooling = 1;
    for (uint16_t i : near.clumps) {
      const ClumpState& c = w.clumps[i];
      const double r2 = dot(p - c.center, p - c.center);
      if (r2 >= c.cutoff2) continue;
      const double shock = 1 + sqr(sqr(r2 / sqr(c.shock_radius)));  // 1 + (r/R)^8: a sharp edge
      heat += c.virial_temperature * window(r2, c.cutoff2) / shock;
      cooling *= sqr(r2 / (r2 + c.cooling2));
    }
    for (uint16_t i : near.filaments) {
      const FilamentState& f = w.filaments[i];
      heat += 4e5 * (f.amplitude / 20) * filament_kernel(segment_distance2(p, f));
    }
    return kTemperatureFloor + heat * cooling;
  }

  int steps_;
  std::vector<Clump> clumps_;
  std::vector<Filament> filaments_;
  Wave waves_[3];
  Universe final_;
  double max_background_ = 0;  // the final background's largest value
  std::unique_ptr<NeighbourBins> bins_;
};

}  // namespace cosmo

// =================================================================================================
// The source: a recorded octree plus a model to evaluate.
// =================================================================================================

class DemoSource final : public AmrSource {
 public:
  DemoSource(std::unique_ptr<DemoModel> model, OctreeShape shape, int steps)
      : model_(std::move(model)), shape_(std::move(shape)), steps_(steps) {}

  std::vector<Cell> take_cells() override {
    std::vector<Cell> cells(shape_.cell_count());
    for_each_leaf(shape_, [&](uint64_t i, const Cell& c) { cells[i] = c; });
    return cells;
  }
  uint64_t cell_count() const override { return shape_.cell_count(); }
  WorldTransform transform() const override { return {shape_.grid.origin, vec3d(shape_.grid.finest)}; }
  std::vector<std::string> field_names() const override { return model_->field_names(); }
  int step_count() const override { return steps_; }
  double step_time(int step) const override { return model_->step_time(step); }

  void read_values(int field, int step, float* out) override {
    if (field < 0 || field >= int(model_->field_names().size()) || step < 0 || step >= steps_)
      throw std::out_of_range("demo: no field " + std::to_string(field) + " at step " + std::to_string(step));
    const FieldFunction f = model_->field(field, step);
    const RootGrid& g = shape_.grid;
    for_each_leaf(shape_, [&](uint64_t i, const Cell& c) { out[i] = f(g.node(c).center); });
  }

  std::string description() const override {
    return "demo " + model_->name() + " (" + std::to_string(shape_.grid.levels) + " levels)";
  }

 private:
  std::unique_ptr<DemoModel> model_;
  OctreeShape shape_;
  int steps_;
};

}  // namespace

std::vector<std::string> demo_names() { return {"jet", "cosmo"}; }

std::unique_ptr<AmrSource> make_demo(const DemoOptions& options) {
  std::unique_ptr<DemoModel> model;
  if (options.name == "jet")
    model = std::make_unique<jet::JetModel>();
  else if (options.name == "cosmo")
    model = std::make_unique<cosmo::CosmoModel>(options.steps);
  else
    throw UsageError("unknown demo '" + options.name + "' (jet, cosmo)");
  if (options.target_cells < 10'000 || options.target_cells > 2'000'000'000)
    throw UsageError("demo cell count must be between 1e4 and 2e9");
  if (options.steps < 1) throw UsageError("demo needs at least 1 step");

  OctreeShape shape = fit_cell_count(*model, options.target_cells);
  return std::make_unique<DemoSource>(std::move(model), std::move(shape), options.steps);
}

}  // namespace vs
