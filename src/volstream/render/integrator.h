// The per-pixel volume integrator (DVR + isosurfaces through ABRs), one source for CPU and CUDA.
//
// A ray walks the visible ABRs front to back (bvh_next_leaf on the refit BVH). Each ABR segment
// [t0, t1] is cut into n equal steps no longer than the ABR's finest cell width / rate (adaptive
// sampling), sampled with the tent basis over that ABR's bricks only, and composited front to
// back with opacity correction for the step length. Isosurfaces are found as sign changes of
// f - iso between consecutive samples (also across adjacent ABRs), refined by bisection and a
// final secant step, shaded with the gradient and composited in the same march.
//
// Units: the ray is generated in world space with a unit direction, so its parameter t is a
// world distance; origin and direction are mapped to grid units (anisotropic scale allowed)
// and the same t addresses the same point in both spaces.
#pragma once
#include <cmath>
#include <cstdint>

#include "volstream/accel/bvh_traverse.h"
#include "volstream/amr/model.h"
#include "volstream/amr/sampler.h"
#include "volstream/render/camera.h"
#include "volstream/render/transfer_function.h"

namespace vs {

inline constexpr uint32_t kMaxIso = 8;
inline constexpr float kOpaque = 0.99f;  // early ray termination
inline constexpr float kFaceInset = 1e-3f;  // fraction of a step that samples keep off ABR faces

struct GridMap {
  vec3f origin{0.f, 0.f, 0.f};         // world position of grid point 0
  vec3f inv_cell_size{1.f, 1.f, 1.f};  // grid units per world unit, per axis
};

struct IntegratorSettings {
  float rate = 2.f;          // samples per cell width (the ABR's finest width when adaptive)
  uint32_t adaptive = 1;     // 0: step at the dataset's finest width in every ABR
  float ref_step = 1.f;      // world length over which a table alpha applies unchanged
  uint32_t jitter = 1;       // per-pixel start offset against wood-grain (deterministic hash)
  uint32_t shade = 0;        // gradient (headlight) shading of the volume
  uint32_t spp = 1;          // rays per pixel; > 1 spreads them over the pixel
  uint32_t seed = 0;         // varies the jitter pattern
  uint32_t iso_count = 0;
  float iso[kMaxIso] = {};
  float iso_alpha = 1.f;     // opacity of the isosurfaces
};

// Everything a kernel reads: plain pointers (host or device) and values.
struct RenderView {
  AmrView amr;                           // topology + the primary field's values
  const float* color_values = nullptr;   // optional second field colouring the isosurfaces
  const BvhNode* nodes = nullptr;        // refit BVH: culled ABRs have empty boxes
  uint32_t node_count = 0;
  const BvhNode* all_nodes = nullptr;    // template BVH over all ABRs: point location for gradients
  uint32_t all_node_count = 0;
  TfView tf;                             // primary field: colour and opacity
  TfView color_tf;                       // colours for color_values
  CameraView camera;
  GridMap grid;
  IntegratorSettings settings;
  uint32_t width = 0, height = 0;
  float* rgba = nullptr;                 // output: width*height premultiplied linear RGBA
  uint32_t* sample_counts = nullptr;     // optional output: samples taken per pixel
};

namespace detail {

VS_HOST_DEVICE inline uint32_t hash32(uint32_t x) {  // "lowbias32" integer hash
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}
VS_HOST_DEVICE inline float hash_unit(uint32_t a, uint32_t b, uint32_t c) {  // in [0, 1)
  return float(hash32(a ^ hash32(b ^ hash32(c))) >> 8) * (1.f / 16777216.f);
}
VS_HOST_DEVICE inline float fract(float x) { return x - floorf(x); }
VS_HOST_DEVICE inline bool is_nan(float x) { return x != x; }  // no <cmath> overload puzzles on host/device

VS_HOST_DEVICE inline void composite(Rgba& acc, float r, float g, float b, float alpha) {
  const float w = (1.f - acc.a) * alpha;
  acc.r += w * r;
  acc.g += w * g;
  acc.b += w * b;
  acc.a += w;
}

// Field value at p (grid units) near ABR `abr`: that ABR's bricks when p is inside its box, else
// the ABR containing p (gradient stencils reach across ABR faces). NaN outside the volume.
VS_HOST_DEVICE inline float sample_near(const RenderView& v, const AmrView& amr, uint32_t abr, const vec3f& p) {
  if (amr.abrs[abr].box.contains(p)) return sample_abr(amr, abr, p);
  const int64_t other = bvh_locate(v.all_nodes, v.all_node_count, [&](uint32_t i) { return amr.abrs[i].box; }, p);
  return other < 0 ? NAN : sample_abr(amr, uint32_t(other), p);
}

// Gradient in world units by central differences (one-sided at the volume's edge).
VS_HOST_DEVICE inline vec3f world_gradient(const RenderView& v, uint32_t abr, const vec3f& p, float f) {
  const float h = 0.5f * v.amr.abrs[abr].finest_width;
  vec3f g;
  for (int a = 0; a < 3; ++a) {
    vec3f pp = p, pm = p;
    pp[a] += h;
    pm[a] -= h;
    const float fp = sample_near(v, v.amr, abr, pp), fm = sample_near(v, v.amr, abr, pm);
    const bool okp = !is_nan(fp), okm = !is_nan(fm);
    g[a] = okp && okm ? (fp - fm) / (2.f * h) : okp ? (fp - f) / h : okm ? (f - fm) / h : 0.f;
  }
  return g * v.grid.inv_cell_size;  // d/dworld = d/dgrid * dgrid/dworld
}

// Headlight Blinn-Phong, two-sided: the light sits at the eye, so the half vector is the view
// direction and only |n . view| matters.
VS_HOST_DEVICE inline Rgba headlight(const Rgba& c, const vec3f& gradient, const vec3f& view_dir, float ambient,
                                     float specular) {
  const float len = length(gradient);
  if (!(len > 0.f)) return c;
  const float cosine = fabsf(dot(gradient, view_dir)) / len;
  const float diffuse = ambient + (1.f - ambient) * cosine;
  const float c2 = cosine * cosine, c4 = c2 * c2, c8 = c4 * c4, c16 = c8 * c8;
  const float spec = specular * c16 * c16;  // shininess 32
  return {c.r * diffuse + spec, c.g * diffuse + spec, c.b * diffuse + spec, c.a};
}

// The last valid sample: where an isosurface crossing to the next sample begins.
struct PrevSample {
  bool valid = false;
  float t = 0.f, f = 0.f;
  uint32_t abr = 0;
  float end = 0.f;  // exit distance of that sample's ABR segment
};

struct Ray {
  vec3f org_w, dir_w;  // world
  vec3f org, dir;      // grid units, same parameter t
  float dir_len;       // |dir| in grid units per unit t
  VS_HOST_DEVICE vec3f at(float t) const { return org + dir * t; }
};

struct RayState {
  Rgba acc;  // premultiplied
  PrevSample prev;
  uint32_t samples = 0;
};

// f between sample a (in ABR abr_a, whose segment ends at end_a) and sample b (ABR abr_b).
struct Bracket {
  float ta, fa, tb, fb, end_a;
  uint32_t abr_a, abr_b;
  VS_HOST_DEVICE uint32_t abr_at(float t) const { return t <= end_a ? abr_a : abr_b; }
};

// Root of f - iso in the bracket: 4 bisection steps (robust), then a secant step (accurate).
// Returns NaN when f does not pass through iso continuously: where the weights of the tent basis
// vanish (the half-cell shell around the cells) f can jump between ABRs, and bisection then
// closes in on the jump, where f stays far from iso.
VS_HOST_DEVICE inline float refine_root(const RenderView& v, const Ray& ray, const Bracket& br, float iso,
                                        RayState& s) {
  auto g = [&](float t) {
    ++s.samples;
    return sample_abr(v.amr, br.abr_at(t), ray.at(t)) - iso;
  };
  float ta = br.ta, ga = br.fa - iso, tb = br.tb, gb = br.fb - iso;
  for (int i = 0; i < 4; ++i) {
    const float tm = 0.5f * (ta + tb);
    const float gm = g(tm);
    if (is_nan(gm)) return NAN;
    if ((gm < 0.f) == (ga < 0.f)) {
      ta = tm;
      ga = gm;
    } else {
      tb = tm;
      gb = gm;
    }
  }
  const float t = ta + (tb - ta) * ga / (ga - gb);  // ga, gb have opposite signs: no 0/0
  const float residual = g(t);
  return fabsf(residual) <= 0.05f * fabsf(br.fa - br.fb) ? t : NAN;
}

// Composites the isosurfaces crossed between the two samples of `br`, nearest first.
VS_HOST_DEVICE inline void isosurfaces(const RenderView& v, const Ray& ray, const Bracket& br, RayState& s) {
  const IntegratorSettings& st = v.settings;
  float hit_t[kMaxIso];
  uint32_t hit_iso[kMaxIso];
  uint32_t n = 0;
  for (uint32_t i = 0; i < st.iso_count && i < kMaxIso; ++i) {
    if ((br.fa - st.iso[i] < 0.f) == (br.fb - st.iso[i] < 0.f)) continue;
    const float t = refine_root(v, ray, br, st.iso[i], s);
    if (is_nan(t)) continue;
    uint32_t k = n++;
    for (; k > 0 && hit_t[k - 1] > t; --k) {  // insertion sort by distance
      hit_t[k] = hit_t[k - 1];
      hit_iso[k] = hit_iso[k - 1];
    }
    hit_t[k] = t;
    hit_iso[k] = i;
  }
  for (uint32_t k = 0; k < n && s.acc.a < kOpaque; ++k) {
    const uint32_t abr = br.abr_at(hit_t[k]);
    const vec3f p = ray.at(hit_t[k]);
    Rgba c = v.tf.lookup(st.iso[hit_iso[k]]);
    if (v.color_values) {
      AmrView cv = v.amr;
      cv.values = v.color_values;
      const float cf = sample_near(v, cv, abr, p);
      if (!is_nan(cf)) c = v.color_tf.lookup(cf);
    }
    const vec3f g = world_gradient(v, abr, p, st.iso[hit_iso[k]]);
    s.samples += 6;
    const Rgba lit = headlight(c, g, ray.dir_w, 0.2f, 0.35f);
    composite(s.acc, lit.r, lit.g, lit.b, st.iso_alpha);
  }
}

// The previous segment ended and the next one does not touch it (culled ABRs in between): check
// the stretch from the last sample to that segment's exit, then forget it.
VS_HOST_DEVICE inline void close_segment(const RenderView& v, const Ray& ray, RayState& s) {
  if (!s.prev.valid) return;
  const PrevSample& p = s.prev;
  // Just inside the exit face: on a face where two bricks' supports meet edge to edge the
  // weights vanish and f is 0/0, while it is defined arbitrarily close to it.
  const float t_end = p.end - kFaceInset * (p.end - p.t);
  const float f_end = sample_abr(v.amr, p.abr, ray.at(t_end));
  ++s.samples;
  if (!is_nan(f_end) && t_end > p.t) isosurfaces(v, ray, {p.t, p.f, t_end, f_end, p.end, p.abr, p.abr}, s);
  s.prev.valid = false;
}

// Volume sample f at distance t inside ABR `abr`: isosurfaces since the previous sample, then
// the emission-absorption contribution of one step (alpha corrected for the step length).
VS_HOST_DEVICE inline void take_sample(const RenderView& v, const Ray& ray, uint32_t abr, float t, float seg_end, float f,
                                       float exponent, RayState& s) {
  if (v.settings.iso_count > 0 && s.prev.valid)
    isosurfaces(v, ray, {s.prev.t, s.prev.f, t, f, s.prev.end, s.prev.abr, abr}, s);
  Rgba c = v.tf.lookup(f);
  if (c.a > 0.f && s.acc.a < kOpaque) {
    // alpha' = 1 - (1 - alpha)^(dt / dt_ref)
    const float alpha = c.a >= 1.f ? 1.f : 1.f - exp2f(exponent * log2f(1.f - c.a));
    if (v.settings.shade) {
      c = headlight(c, world_gradient(v, abr, ray.at(t), f), ray.dir_w, 0.35f, 0.25f);
      s.samples += 6;
    }
    composite(s.acc, c.r, c.g, c.b, alpha);
  }
  s.prev = {true, t, f, abr, seg_end};
}

// Marches one ABR segment [hit.t0, hit.t1] with n equal steps of at most width / rate.
VS_HOST_DEVICE inline void march_segment(const RenderView& v, const Ray& ray, const LeafHit& hit, float jitter,
                                         RayState& s) {
  const IntegratorSettings& st = v.settings;
  const float len = hit.t1 - hit.t0;
  if (!(len > 0.f)) return;
  const float width = st.adaptive ? v.amr.abrs[hit.item].finest_width : 1.f;
  const float max_dt = width / (st.rate * ray.dir_len);
  const float steps = ceilf(len / max_dt);
  const uint32_t n = steps < 1.f ? 1u : (steps < 16777216.f ? uint32_t(steps) : 16777216u);  // no float->int overflow
  const float dt = len / float(n);
  const float exponent = dt / st.ref_step;
  if (st.iso_count > 0) {
    if (s.prev.valid && hit.t0 - s.prev.end > 1e-4f * dt) close_segment(v, ray, s);
    if (!s.prev.valid) {  // start the crossing test at the segment's entry face (just inside)
      const float t0 = hit.t0 + kFaceInset * dt;
      const float f0 = sample_abr(v.amr, hit.item, ray.at(t0));
      ++s.samples;
      if (!is_nan(f0)) s.prev = {true, t0, f0, hit.item, hit.t1};
    }
  }
  for (uint32_t k = 0; k < n; ++k) {
    const float t = hit.t0 + (float(k) + jitter) * dt;
    const float f = sample_abr(v.amr, hit.item, ray.at(t));
    ++s.samples;
    if (is_nan(f)) {  // outside every cell's support (the volume's boundary faces)
      s.prev.valid = false;
      continue;
    }
    take_sample(v, ray, hit.item, t, hit.t1, f, exponent, s);
    if (s.acc.a >= kOpaque) return;
  }
}

VS_HOST_DEVICE inline RayState trace_ray(const RenderView& v, const vec3f& org_w, const vec3f& dir_w, float jitter) {
  Ray ray;
  ray.org_w = org_w;
  ray.dir_w = dir_w;
  ray.org = (org_w - v.grid.origin) * v.grid.inv_cell_size;
  ray.dir = dir_w * v.grid.inv_cell_size;
  ray.dir_len = length(ray.dir);
  const SlabRay slab(ray.org, ray.dir);
  RayState s;
  // Segments come K at a time from one traversal, front to back.
  constexpr int kBatch = 16;
  LeafHit hits[kBatch];
  float t = 0.f;
  for (;;) {
    const int n = bvh_next_leaves<kBatch>(v.nodes, v.node_count, slab, t, INFINITY, hits);
    for (int i = 0; i < n; ++i) {
      march_segment(v, ray, hits[i], jitter, s);
      if (s.acc.a >= kOpaque) return s;
    }
    if (n < kBatch) break;
    t = hits[kBatch - 1].t1;
  }
  if (v.settings.iso_count > 0) close_segment(v, ray, s);
  return s;
}

}  // namespace detail

// Renders pixel (x, y) into v.rgba (and v.sample_counts when given).
VS_HOST_DEVICE inline void render_pixel(const RenderView& v, uint32_t x, uint32_t y) {
  const IntegratorSettings& st = v.settings;
  const uint32_t spp = st.spp > 0 ? st.spp : 1u;
  const uint32_t pixel = y * v.width + x;
  // Per-pixel random offsets, shifted per ray by low-discrepancy sequences (R2 on the pixel,
  // golden ratio in depth), so several rays per pixel stratify instead of clumping.
  const float rx = detail::hash_unit(x, y, st.seed * 3u + 1u), ry = detail::hash_unit(x, y, st.seed * 3u + 2u);
  const float rz = detail::hash_unit(x, y, st.seed * 3u + 3u);
  Rgba sum;
  uint32_t samples = 0;
  for (uint32_t i = 0; i < spp; ++i) {
    const float sx = spp > 1 ? detail::fract(rx + 0.7548776662f * float(i)) : 0.5f;
    const float sy = spp > 1 ? detail::fract(ry + 0.5698402910f * float(i)) : 0.5f;
    float jitter = st.jitter ? detail::fract(rz + 0.6180339887f * float(i)) : 0.5f;
    jitter = kFaceInset + (1.f - 2.f * kFaceInset) * jitter;  // never exactly on an ABR face
    vec3f org, dir;
    v.camera.ray(float(x) + sx, float(y) + sy, org, dir);
    const detail::RayState s = detail::trace_ray(v, org, dir, jitter);
    sum.r += s.acc.r;
    sum.g += s.acc.g;
    sum.b += s.acc.b;
    sum.a += s.acc.a;
    samples += s.samples;
  }
  const float inv = 1.f / float(spp);
  float* out = v.rgba + 4 * size_t(pixel);
  out[0] = sum.r * inv;
  out[1] = sum.g * inv;
  out[2] = sum.b * inv;
  out[3] = sum.a * inv;
  if (v.sample_counts) v.sample_counts[pixel] = samples;
}

}  // namespace vs
