// VTK's interpolation inside the linear 3D cells, and its inverse (point location in one cell):
//   tetra       barycentric: w = (1-r-s-t, r, s, t)
//   hexahedron  trilinear over r,s,t in [0,1]^3, vertices 0-3 at t = 0, 4-7 above them
//   wedge       linear on the triangles 0-1-2 (t = 0) and 3-4-5 (t = 1) times linear in t:
//               w = ((1-r-s)(1-t), r(1-t), s(1-t), (1-r-s)t, rt, st)
//   pyramid     the base quad 0-3 collapsed to the apex 4: w_0..3 = bilinear(r,s)*(1-t), w_4 = t
// The non-tet maps are inverted by Newton iteration from the cell's centre, so twisted hexes and
// non-planar faces are located exactly on their curved (ruled) faces, as VTK's EvaluatePosition
// does. A point is inside when its parametric coordinates are, within kParamTolerance (shared
// faces then belong to both neighbours, which interpolate the same value there; an element that
// holds the point strictly is preferred, see UMeshView::locate).
#pragma once
#include <cmath>

#include "volstream/core/math.h"
#include "volstream/umesh/umesh.h"
#if defined(__GNUC__) && !defined(__CUDACC__)
#include "volstream/core/simd.h"  // the host's lanes below
#endif

namespace vs::shape {

inline constexpr float kParamTolerance = 1e-4f;
inline constexpr int kNewtonIterations = 16;

// Weights w[0..n) at parametric r, s, t for an element of n vertices; and their derivatives
// d[i] = (dw_i/dr, dw_i/ds, dw_i/dt).
VS_HOST_DEVICE inline void weights(int n, float r, float s, float t, float* w, vec3f* d) {
  const float rm = 1.f - r, sm = 1.f - s, tm = 1.f - t;
  if (n == 4) {
    w[0] = 1.f - r - s - t, w[1] = r, w[2] = s, w[3] = t;
    d[0] = {-1.f, -1.f, -1.f}, d[1] = {1.f, 0.f, 0.f}, d[2] = {0.f, 1.f, 0.f}, d[3] = {0.f, 0.f, 1.f};
  } else if (n == 8) {
    const float rr[8] = {rm, r, r, rm, rm, r, r, rm}, ss[8] = {sm, sm, s, s, sm, sm, s, s},
                tt[8] = {tm, tm, tm, tm, t, t, t, t};
    const float dr[8] = {-1, 1, 1, -1, -1, 1, 1, -1}, ds[8] = {-1, -1, 1, 1, -1, -1, 1, 1},
                dt[8] = {-1, -1, -1, -1, 1, 1, 1, 1};
    for (int i = 0; i < 8; ++i) {
      w[i] = rr[i] * ss[i] * tt[i];
      d[i] = {dr[i] * ss[i] * tt[i], rr[i] * ds[i] * tt[i], rr[i] * ss[i] * dt[i]};
    }
  } else if (n == 6) {
    const float u = 1.f - r - s;
    w[0] = u * tm, w[1] = r * tm, w[2] = s * tm, w[3] = u * t, w[4] = r * t, w[5] = s * t;
    d[0] = {-tm, -tm, -u}, d[1] = {tm, 0.f, -r}, d[2] = {0.f, tm, -s};
    d[3] = {-t, -t, u}, d[4] = {t, 0.f, r}, d[5] = {0.f, t, s};
  } else {  // pyramid
    w[0] = rm * sm * tm, w[1] = r * sm * tm, w[2] = r * s * tm, w[3] = rm * s * tm, w[4] = t;
    d[0] = {-sm * tm, -rm * tm, -rm * sm}, d[1] = {sm * tm, -r * tm, -r * sm};
    d[2] = {s * tm, r * tm, -r * s}, d[3] = {-s * tm, rm * tm, -rm * s}, d[4] = {0.f, 0.f, 1.f};
  }
}

// The faces of each type, numbered by the parameter bound they lie on (the walk in
// element_bvh.h crosses the face that p violates most; umesh/adjacency.h pairs faces up):
//   tetra       face k opposite vertex k (weight w_k = 0)
//   hexahedron  r = 0, r = 1, s = 0, s = 1, t = 0, t = 1
//   wedge       r = 0, s = 0, r + s = 1, t = 0, t = 1
//   pyramid     r = 0, r = 1, s = 0, s = 1, t = 0 (the base)
inline constexpr int kMaxFaces = 6;
VS_HOST_DEVICE constexpr int face_count(int n) { return n == 4 ? 4 : n == 8 ? 6 : 5; }

// The element-local vertices of face `face` of an element of n vertices, in the numbering above.
struct LocalFace {
  int count;  // 3 or 4
  int v[4];   // element-local vertex indices
};
VS_HOST_DEVICE inline LocalFace local_face(int n, int face) {
  constexpr LocalFace kTet[4] = {{3, {1, 2, 3, 0}}, {3, {0, 2, 3, 0}}, {3, {0, 1, 3, 0}}, {3, {0, 1, 2, 0}}};
  constexpr LocalFace kHex[6] = {{4, {0, 3, 7, 4}}, {4, {1, 2, 6, 5}}, {4, {0, 1, 5, 4}},
                                 {4, {3, 2, 6, 7}}, {4, {0, 1, 2, 3}}, {4, {4, 5, 6, 7}}};
  constexpr LocalFace kWedge[5] = {
      {4, {0, 2, 5, 3}}, {4, {0, 1, 4, 3}}, {4, {1, 2, 5, 4}}, {3, {0, 1, 2, 0}}, {3, {3, 4, 5, 0}}};
  constexpr LocalFace kPyramid[5] = {
      {3, {0, 3, 4, 0}}, {3, {1, 2, 4, 0}}, {3, {0, 1, 4, 0}}, {3, {3, 2, 4, 0}}, {4, {0, 1, 2, 3}}};
  return n == 4 ? kTet[face] : n == 8 ? kHex[face] : n == 6 ? kWedge[face] : kPyramid[face];
}

// Each face's violation at (r, s, t) (> 0: p lies beyond that face); returns the face count.
VS_HOST_DEVICE inline int face_violations(int n, float r, float s, float t, float* v) {
  if (n == 4) {
    v[0] = r + s + t - 1.f, v[1] = -r, v[2] = -s, v[3] = -t;
    return 4;
  }
  if (n == 6) {
    v[0] = -r, v[1] = -s, v[2] = r + s - 1.f, v[3] = -t, v[4] = t - 1.f;
    return 5;
  }
  v[0] = -r, v[1] = r - 1.f, v[2] = -s, v[3] = s - 1.f, v[4] = -t, v[5] = t - 1.f;
  return n == 8 ? 6 : 5;
}

// The first of v[0..count) that is largest (a NaN after v[0] never wins), and its value in
// `most`, by selects over all kMaxFaces slots rather than a branch per face: which face a point
// lies beyond most is as good as random, and every Newton step asks.
VS_HOST_DEVICE inline int first_largest(const float* v, int count, float& most) {
  int worst = 0;
  most = v[0];
  for (int f = 1; f < kMaxFaces; ++f) {
    const float vf = f < count ? v[f] : -INFINITY;
    const bool beyond = vf > most;
    worst = beyond ? f : worst;
    most = beyond ? vf : most;
  }
  return worst;
}

// How far the parametric point lies outside the element's parameter domain (<= 0: inside), and
// the face it lies beyond most. Forced inline: out of line (where GCC's heuristics put it), the
// selects above compile to branches again (cachegrind: 0.7 M more mispredicts on the mixed haze).
VS_HOST_DEVICE VS_FORCE_INLINE float params_outside(int n, float r, float s, float t, int* face = nullptr) {
  float v[kMaxFaces];
  const int count = face_violations(n, r, s, t, v);
  float most;
  const int worst = first_largest(v, count, most);
  if (n == 5 && t > 1.f && most < t - 1.f) return t - 1.f;  // above the apex: no face there
  if (face) *face = worst;
  return most;
}

#if defined(__GNUC__) && !defined(__CUDACC__)
// The host's 3-vectors on 4 float lanes (x, y, z, unused), GCC/Clang vector extensions, for
// Newton's step (newton_step): on vec3f the compiler spills the map's 24 coefficients to the
// stack; on lanes they stay in registers, and the Newton loop of the mixed demo's haze render
// runs a third fewer instructions (callgrind, bench/RESULTS.md). The lanes compute the same
// expressions in the same order (cross products lane by lane, dots summed x + y + z), so without
// contraction into FMA (the default build: none on x86-64-v2) both give the same floats;
// tests/umesh/shape_test.cpp compares them. CUDA keeps vec3f.
#define VS_SHAPE_LANES 1
namespace lanes {
using simd::f4, simd::i4;
#if defined(__clang__)
inline f4 yzx(f4 v) { return __builtin_shufflevector(v, v, 1, 2, 0, 3); }
inline f4 zxy(f4 v) { return __builtin_shufflevector(v, v, 2, 0, 1, 3); }
#else
inline f4 yzx(f4 v) { return __builtin_shuffle(v, i4{1, 2, 0, 3}); }
inline f4 zxy(f4 v) { return __builtin_shuffle(v, i4{2, 0, 1, 3}); }
#endif
inline f4 cross(f4 a, f4 b) { return yzx(a) * zxy(b) - zxy(a) * yzx(b); }
inline float dot(f4 a, f4 b) {
  const f4 m = a * b;
  return m[0] + m[1] + m[2];
}
}  // namespace lanes
using lanes::cross, lanes::dot, vs::cross, vs::dot;  // one overload set for both kinds
#endif

// Solves J x = b for a 3x3 J given by its columns; false when J is (nearly) singular. V: vec3f,
// or the host's lanes (above).
template <typename V>
VS_HOST_DEVICE inline bool solve3(const V& c0, const V& c1, const V& c2, const V& b, vec3f& x) {
  const V r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
  const float det = dot(c0, r0);
  if (!(fabsf(det) > 1e-30f)) return false;
  const float inv = 1.f / det;
  x = {dot(b, r0) * inv, dot(b, r1) * inv, dot(b, r2) * inv};
  return true;
}

// Parametric start of the Newton iteration: the cell's centre.
VS_HOST_DEVICE inline vec3f centre_params(int n) {
  return n == 4   ? vec3f(0.25f)
         : n == 6 ? vec3f(1.f / 3.f, 1.f / 3.f, 0.5f)
         : n == 5 ? vec3f(0.5f, 0.5f, 0.2f)
                  : vec3f(0.5f);
}

// The tet's map is affine: its barycentric coordinates come from one 3x3 solve (the hot path of
// tet meshes, kept free of the general Newton loop's arrays). TetSolve is that solve's part that
// does not depend on p (Cramer's rule: the cofactor rows and 1 / det), so a walk can keep it and
// test its next point in the same tet without the corners (element_bvh.h); tet_weights then
// gives the same floats as the whole solve.
struct TetSolve {
  vec3f origin;       // corner 0
  vec3f rows[3];      // cross products of the edge vectors from corner 0
  float inv_det = 0;  // 1 / det of those edges
};
VS_HOST_DEVICE inline bool tet_solve(const vec3f* x, TetSolve& s) {
  const vec3f c0 = x[1] - x[0], c1 = x[2] - x[0], c2 = x[3] - x[0];
  s.origin = x[0];
  s.rows[0] = cross(c1, c2), s.rows[1] = cross(c2, c0), s.rows[2] = cross(c0, c1);
  const float det = dot(c0, s.rows[0]);
  if (!(fabsf(det) > 1e-30f)) return false;
  s.inv_det = 1.f / det;
  return true;
}
// A tet's weights (w[0..4)) from its parametric point pc, and the face p lies beyond most: the
// one opposite the most negative weight.
VS_HOST_DEVICE inline int tet_weights_of(const vec3f& pc, float* w) {
  const float w0 = 1.f - pc.x - pc.y - pc.z;
  w[0] = w0, w[1] = pc.x, w[2] = pc.y, w[3] = pc.z;
  // The smallest as a tournament of selects on the values in registers (the first of equals, as
  // a scan would give): a scan reads w[worst] back through memory and branches on each step, the
  // render's hottest branch (the next face is random).
  const bool low_1 = pc.x < w0, low_3 = pc.z < pc.y;
  const float least_01 = low_1 ? pc.x : w0, least_23 = low_3 ? pc.z : pc.y;
  return least_23 < least_01 ? (low_3 ? 3 : 2) : (low_1 ? 1 : 0);
}
// The weights at p (w[0..4)), how far outside p is and the face it lies beyond most, as in
// locate_in_element; true when p is inside within kParamTolerance.
VS_HOST_DEVICE inline bool tet_weights(const TetSolve& s, const vec3f& p, float* w, float* outside, int* face) {
  const vec3f b = p - s.origin;
  const int worst =
      tet_weights_of({dot(b, s.rows[0]) * s.inv_det, dot(b, s.rows[1]) * s.inv_det, dot(b, s.rows[2]) * s.inv_det}, w);
  if (face) *face = worst;
  if (outside) *outside = -w[worst];
  return -w[worst] <= kParamTolerance;
}
// `kept` (optional) gets the solve, valid when `face` was set (the corners were not degenerate).
VS_HOST_DEVICE inline bool locate_in_tet(const vec3f* x, const vec3f& p, float* w, float* outside, int* face,
                                         TetSolve* kept = nullptr) {
  TetSolve s;
  if (!tet_solve(x, s)) return false;
  if (kept) *kept = s;
  return tet_weights(s, p, w, outside, face);
}

// The map of a hex, wedge or pyramid as a polynomial in r, s, t: x = c[0] + c[1] r + c[2] s +
// c[3] t + c[4] rs + c[5] rt + c[6] st + c[7] rst, expanded from VTK's weights once per element,
// so that each Newton step costs a few products instead of every corner's weights and
// derivatives (the same map: the root and the final weights are VTK's).
struct IsoMap {
  vec3f c[8];
};
VS_HOST_DEVICE inline IsoMap iso_map(int n, const vec3f* x) {
  const vec3f o = x[0];
  if (n == 8) {
    const vec3f r = x[1] - o, s = x[3] - o, t = x[4] - o;
    return {
        {o, r, s, t, x[2] - x[3] - r, x[5] - x[4] - r, x[7] - x[4] - s, x[6] - x[7] - x[5] + x[4] - (x[2] - x[3] - r)}};
  }
  if (n == 6) {  // bilinear in (r, t) and (s, t): no rs or rst terms
    const vec3f r = x[1] - o, s = x[2] - o, t = x[3] - o;
    return {{o, r, s, t, vec3f(0.f), x[4] - x[3] - r, x[5] - x[3] - s, vec3f(0.f)}};
  }
  // pyramid: the bilinear base times (1 - t), plus the apex times t
  const vec3f r = x[1] - o, s = x[3] - o, rs = x[2] - x[3] - r;
  return {{o, r, s, x[4] - o, rs, vec3f(0.f) - r, vec3f(0.f) - s, vec3f(0.f) - rs}};
}

// One Newton step of the map towards p from the parametric point pc; false when its Jacobian is
// (nearly) singular there.
// c: the map's coefficients as V (vec3f, or the host's lanes).
template <typename V>
VS_HOST_DEVICE inline bool newton_step(const V* c, const V& p, const vec3f& pc, vec3f& delta) {
  const float r = pc.x, s = pc.y, t = pc.z;
  const V dr = c[1] + c[4] * s + (c[5] + c[7] * s) * t;  // dx/dr
  const V ds = c[2] + c[4] * r + (c[6] + c[7] * r) * t;
  const V dt = c[3] + c[5] * r + (c[6] + c[7] * r) * s;
  const V pos = c[0] + c[2] * s + (c[1] + c[4] * s) * r + (c[3] + c[6] * s) * t + (c[5] + c[7] * s) * (r * t);
  return solve3(dr, ds, dt, p - pos, delta);
}
VS_HOST_DEVICE inline bool newton_step(const IsoMap& m, const vec3f& p, const vec3f& pc, vec3f& delta) {
  return newton_step(m.c, p, pc, delta);
}

// Newton's steps shrink quadratically near the root (each about C times the previous squared),
// so after steps `previous` then `step` the next would be about step * (step / previous)^2; once
// that is below float noise, the point just reached is the root (this saves the step that only
// measured noise), given a step already small (a large one says nothing of the root). The gate
// of 1e-2 lets the second step from an element's centre end the iteration: on the mixed demo's
// haze its hexes' and wedges' second steps are mostly 1e-5 to 1e-2, and their third ones only
// measured float noise, 1e-8 to 1e-7 (bench/RESULTS.md). Where the iteration converges only linearly
// (ratio r, about 1/2 at a singular root), the estimate is step * r^2: it passes only with
// r < sqrt(1e-7 / step), at most 3.2e-3, far below what such a root gives. The first step
// (previous = 0) has no estimate.
VS_HOST_DEVICE inline bool newton_converged(float step, float previous) {
  const float ratio = step / previous;
  return step < 1e-6f || (step < 1e-2f && step * ratio * ratio < 1e-7f);
}

// After a step of size `step`, Newton's parametric point is off the root by less than the step
// (the iteration contracts), so a point further outside than that (and than kParamTolerance) is
// outside: a walk can move on without converging (the face to cross is known well enough).
// Two steps in, a point a quarter of the element away is outside whatever the step.
VS_HOST_DEVICE inline bool newton_shows_outside(int n, const vec3f& pc, float step, int* face) {
  const float margin = kParamTolerance + step;
  return params_outside(n, pc.x, pc.y, pc.z, face) > (margin < 0.25f ? margin : 0.25f);
}

// A hex's, wedge's or pyramid's map as Newton inverts it: the polynomial form relative to corner
// 0 (coordinates of the element's size, so float rounding stays far below the Newton tolerance
// however far the element is from the grid's origin), and the parametric point found last (a
// walk keeps it: the next point, close by, starts its iteration there).
struct IsoSolve {
  vec3f origin;  // corner 0
  IsoMap map;
  vec3f params;
};
VS_HOST_DEVICE inline IsoSolve iso_solve(int n, const vec3f* x) {
  vec3f local[8];
  for (int i = 0; i < n; ++i) local[i] = x[i] - x[0];
  return {x[0], iso_map(n, local), centre_params(n)};
}

// Newton's inversion of s.map at p from s.params, which becomes the point reached; the rest as
// locate_in_element. `first_exit`: the first iteration after which early_out may give up (1 from
// the element's centre, where the first step can be far off; 0 from a kept point nearby).
VS_HOST_DEVICE inline bool iso_weights(int n, IsoSolve& s, const vec3f& p, float* w, float* outside, int* face,
                                       bool early_out, int first_exit = 1) {
  if (face) *face = -1;
  const vec3f target = p - s.origin;
  vec3f& pc = s.params;
  float step = 0.f, previous = 0.f;
  bool converged = false;
#if defined(VS_SHAPE_LANES)
  lanes::f4 map[8];  // loaded once for every step
  for (int i = 0; i < 8; ++i) map[i] = simd::lanes_of(s.map.c[i]);
  const lanes::f4 goal = simd::lanes_of(target);
#else
  const vec3f* map = s.map.c;
  const vec3f& goal = target;
#endif
  for (int it = 0; it < kNewtonIterations; ++it, previous = step) {
    vec3f delta;
    if (!newton_step(map, goal, pc, delta)) return false;
    pc = pc + delta;
    step = fabsf(delta.x) + fabsf(delta.y) + fabsf(delta.z);
    converged = newton_converged(step, previous);
    if (converged) break;
    if (early_out && it >= first_exit && newton_shows_outside(n, pc, step, face)) return false;
    if (!(fabsf(pc.x) < 4.f && fabsf(pc.y) < 4.f && fabsf(pc.z) < 4.f)) return false;  // diverging: far outside
  }
  // Out of iterations: Newton converges quadratically, so a last step this small is float noise,
  // not a slow approach.
  if (!converged && !(step < 1e-4f)) return false;
  const float o = params_outside(n, pc.x, pc.y, pc.z, face);
  if (!(o <= kParamTolerance)) return false;
  if (outside) *outside = o;
  vec3f d[8];
  weights(n, pc.x, pc.y, pc.z, w, d);
  return true;
}

// Interpolation weights of the element with corners x[0..n) at point p; false if p is outside
// (beyond kParamTolerance). `outside` (optional) gets how far outside the parameter domain p is
// (<= 0: strictly inside), so that callers can prefer the element that holds p strictly over a
// neighbour that only takes it within the tolerance (and extrapolates a little).
// `face` (optional) gets the face p lies beyond most, or -1 when p is too far to tell (Newton
// diverged or did not converge), also when false is returned.
// `early_out`: give up as soon as the iteration shows p outside (a walk only needs the face to
// cross then; the answer for a point inside is the same either way).
VS_HOST_DEVICE inline bool locate_in_element(int n, const vec3f* x, const vec3f& p, float* w, float* outside = nullptr,
                                             int* face = nullptr, bool early_out = false) {
  if (n == 4) {
    if (face) *face = -1;
    return locate_in_tet(x, p, w, outside, face);
  }
  IsoSolve s = iso_solve(n, x);
  return iso_weights(n, s, p, w, outside, face, early_out);
}

// A walk's solve of the last element it found a point in, kept for the next point (the ray's
// hint: element_bvh.h, compact.h). Consecutive samples are close, so a walk starts by testing p
// in that element (on the demo meshes p has left it about half the time, and the test gives the
// face to cross); with the solve kept that test loads no corners. A tet's kept solve gives the
// same floats as a fresh one; another type's Newton iteration starts from the previous point,
// which is close: it may give up after its first step when that shows p outside (from the
// element's centre it takes two, newton_shows_outside). Inside, the weights are the fresh ones
// to Newton's tolerance (tests/umesh/shape_test.cpp).
struct KeptSolve {
  int n = 0;  // vertex count of the element whose solve is kept; 0: none
  TetSolve tet;
  IsoSolve iso;

  // p in the kept element (as locate_in_element with early_out). The solve is dropped: a walk
  // keeps it again where it finds p.
  VS_HOST_DEVICE bool locate_again(const vec3f& p, float* w, float* outside, int* face, int& kept_n) {
    kept_n = n;
    n = 0;
    if (kept_n == 4) return tet_weights(tet, p, w, outside, face);
    // Near a pyramid's apex, where its map is singular, Newton from there may reach the mirror
    // root beyond the apex and refuse a point inside (found by the test of this): start from the
    // centre there.
    if (kept_n == 5 && iso.params.z > 0.5f) {
      iso.params = centre_params(5);
      return iso_weights(kept_n, iso, p, w, outside, face, true);
    }
    return iso_weights(kept_n, iso, p, w, outside, face, true, 0);
  }
  // p in the element with corners x[0..count) (locate_in_element with early_out), solving it afresh.
  VS_HOST_DEVICE bool locate(int count, const vec3f* x, const vec3f& p, float* w, float* outside, int* face) {
    if (count == 4) {
      if (face) *face = -1;
      return locate_in_tet(x, p, w, outside, face, &tet);
    }
    iso = iso_solve(count, x);
    return iso_weights(count, iso, p, w, outside, face, true);
  }
};

}  // namespace vs::shape
