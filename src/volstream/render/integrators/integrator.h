// The per-pixel volume integrator, one source for every volume kind (volume/volume.h), every
// optical model (render/optics/optics.h) and both CPU and CUDA.
//
// A ray visits the volume's visible regions front to back. Each region's interval is cut into
// steps no longer than the region's finest width / rate (adaptive sampling), in one of two
// schemes (March: paper 000's equal jittered steps, or paper 004's fixed steps with an exact
// last one); each sample is reconstructed by the volume and composited front to back by the
// optics with opacity corrected for the step length, with early termination at 0.99.
// Isosurfaces are sign changes of f - iso between consecutive samples (also across adjacent
// regions), refined by bisection and a final secant step, shaded with the gradient (a headlight)
// and composited in the same march.
//
// Units: the ray is generated in world space with a unit direction, so its parameter t is a
// world distance; origin and direction are mapped to grid units (anisotropic scale allowed) and
// the same t addresses the same point in both spaces.
#pragma once
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "volstream/render/camera.h"
#include "volstream/render/integrators/settings.h"
#include "volstream/render/optics/optics.h"
#include "volstream/volume/volume.h"

namespace vs {

inline constexpr float kFaceInset = 1e-3f;  // fraction of a step that samples keep off region faces

struct GridMap {
  vec3f origin{0.f, 0.f, 0.f};         // world position of grid point 0
  vec3f inv_cell_size{1.f, 1.f, 1.f};  // grid units per world unit, per axis
};

// Everything a kernel reads: plain pointers (host or device) and values.
template <typename V>
struct FrameView {
  V volume;
  OpticsView optics;
  uint32_t color_isosurfaces = 0;  // colour isosurfaces by field 1 through color_tf
  TfView color_tf;
  CameraView camera;
  GridMap grid;
  IntegratorSettings settings;
  uint32_t width = 0, height = 0;
  // The region of grid space whose light this frame composites (a data-parallel rank's kd box,
  // mpi/partition.h; everything by default), half-open so that neighbouring boxes share no
  // point. Samples outside it are still taken (isosurface crossings and gradients look across
  // it) but add nothing.
  box3f owned{vec3f(-INFINITY), vec3f(INFINITY)};
  float* rgba = nullptr;              // output: width*height premultiplied linear RGBA
  uint32_t* sample_counts = nullptr;  // optional output: samples taken per pixel
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

struct Ray {
  vec3f org_w, dir_w;    // world
  vec3f org, dir;        // grid units, same parameter t
  float dir_len;         // |dir| in grid units per unit t
  bool clipped = false;  // the frame owns only a box of space (FrameView::owned): samples are tested
  VS_HOST_DEVICE vec3f at(float t) const { return org + dir * t; }
};

template <typename V>
VS_HOST_DEVICE inline bool owns(const FrameView<V>& v, const vec3f& p) {
  const box3f& b = v.owned;
  return p.x >= b.lower.x && p.x < b.upper.x && p.y >= b.lower.y && p.y < b.upper.y && p.z >= b.lower.z &&
         p.z < b.upper.z;
}
// Whether the frame owns all of space (the default): then no sample needs the test above.
template <typename V>
VS_HOST_DEVICE inline bool owns_everything(const FrameView<V>& v) {
  const box3f& b = v.owned;
  return b.lower.x == -INFINITY && b.lower.y == -INFINITY && b.lower.z == -INFINITY && b.upper.x == INFINITY &&
         b.upper.y == INFINITY && b.upper.z == INFINITY;
}
// owns(v, ray.at(t)), tested only on a clipped frame's rays (once per ray, not per sample).
template <typename V>
VS_HOST_DEVICE inline bool owns(const FrameView<V>& v, const Ray& ray, float t) {
  return !ray.clipped || owns(v, ray.at(t));
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
  uint32_t region = 0;
  float end = 0.f;  // exit distance of that sample's region interval
};

// The per-ray note of volumes that take a hint (volume.h): V::Hint; nothing for the others.
struct NoHint {};
template <typename V>
struct HintOf {
  using type = NoHint;
};
template <typename V>
requires requires { typename V::Hint; }
struct HintOf<V> {
  using type = typename V::Hint;
};

template <typename V>
struct RayState {
  Accum acc;
  PrevSample prev;
  uint32_t samples = 0;
  // Where the volume found the ray's last sample (an unstructured mesh's element), for volumes
  // that take a hint (volume.h): consecutive samples are close, so it is often right.
  typename HintOf<V>::type hint{};
};

// Early ray termination, where the frame allows it (settings.h).
template <typename V>
VS_HOST_DEVICE inline bool finished(const FrameView<V>& v, const RayState<V>& s) {
  return v.settings.early_termination && s.acc.opaque();
}

// A volume's reconstruction at p, with the ray's hint where the volume takes one.
template <typename V>
VS_FORCE_INLINE VS_HOST_DEVICE float sample(const V& volume, int field, uint32_t region, const vec3f& p,
                                            RayState<V>& s) {
  if constexpr (requires { volume.sample(field, region, p, s.hint); })
    return volume.sample(field, region, p, s.hint);
  else
    return volume.sample(field, region, p);
}
template <typename V>
VS_HOST_DEVICE inline float sample_near(const V& volume, int field, uint32_t region, const vec3f& p, RayState<V>& s) {
  if constexpr (requires { volume.sample_near(field, region, p, s.hint); })
    return volume.sample_near(field, region, p, s.hint);
  else
    return volume.sample_near(field, region, p);
}

// Gradient in world units by central differences (one-sided at the volume's edge).
template <typename V>
VS_HOST_DEVICE inline vec3f world_gradient(const FrameView<V>& v, uint32_t region, const vec3f& p, float f,
                                           RayState<V>& s) {
  const float h = 0.5f * v.volume.step_width(region);
  vec3f g;
  for (int a = 0; a < 3; ++a) {
    vec3f pp = p, pm = p;
    pp[a] += h;
    pm[a] -= h;
    const float fp = sample_near(v.volume, 0, region, pp, s), fm = sample_near(v.volume, 0, region, pm, s);
    const bool okp = !is_nan(fp), okm = !is_nan(fm);
    g[a] = okp && okm ? (fp - fm) / (2.f * h) : okp ? (fp - f) / h : okm ? (f - fm) / h : 0.f;
  }
  return g * v.grid.inv_cell_size;  // d/dworld = d/dgrid * dgrid/dworld
}

// f between sample a (in region_a, whose interval ends at end_a) and sample b (region_b).
struct Bracket {
  float ta, fa, tb, fb, end_a;
  uint32_t region_a, region_b;
  VS_HOST_DEVICE uint32_t region_at(float t) const { return t <= end_a ? region_a : region_b; }
};

// Root of f - iso in the bracket: 4 bisection steps (robust), then a secant step (accurate).
// Returns NaN when f does not pass through iso continuously: where a reconstruction has gaps
// (the half-cell shell of the tent basis, nearest-cell steps) bisection closes in on a jump,
// where f stays far from iso.
template <typename V>
VS_HOST_DEVICE inline float refine_root(const FrameView<V>& v, const Ray& ray, const Bracket& br, float iso,
                                        RayState<V>& s) {
  auto g = [&](float t) {
    ++s.samples;
    return sample(v.volume, 0, br.region_at(t), ray.at(t), s) - iso;
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
template <typename V>
VS_HOST_DEVICE inline void isosurfaces(const FrameView<V>& v, const Ray& ray, const Bracket& br, RayState<V>& s) {
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
  for (uint32_t k = 0; k < n && !finished(v, s); ++k) {
    const uint32_t region = br.region_at(hit_t[k]);
    const vec3f p = ray.at(hit_t[k]);
    if (!owns(v, p)) continue;
    Rgba c = v.optics.tf.lookup(st.iso[hit_iso[k]]);
    if (v.color_isosurfaces) {
      const float cf = sample_near(v.volume, 1, region, p, s);
      if (!is_nan(cf)) c = v.color_tf.lookup(cf);
    }
    const vec3f g = world_gradient(v, region, p, st.iso[hit_iso[k]], s);
    s.samples += 6;
    const Rgba lit = headlight(c, g, ray.dir_w, 0.2f, 0.35f);
    s.acc.blend(lit.r, lit.g, lit.b, st.iso_alpha);
  }
}

// The previous interval ended and the next one does not touch it (culled regions in between):
// check the stretch from the last sample to that interval's exit, then forget it.
template <typename V>
VS_HOST_DEVICE inline void close_interval(const FrameView<V>& v, const Ray& ray, RayState<V>& s) {
  if (!s.prev.valid) return;
  const PrevSample& p = s.prev;
  // Just inside the exit face: on a face where two bricks' supports meet edge to edge the
  // weights vanish and f is 0/0, while it is defined arbitrarily close to it.
  const float t_end = p.end - kFaceInset * (p.end - p.t);
  const float f_end = sample(v.volume, 0, p.region, ray.at(t_end), s);
  ++s.samples;
  if (!is_nan(f_end) && t_end > p.t) isosurfaces(v, ray, {p.t, p.f, t_end, f_end, p.end, p.region, p.region}, s);
  s.prev.valid = false;
}

// Volume sample f at distance t in `region`: isosurfaces since the previous sample, then the
// optics' emission and absorption over len_ref reference steps.
template <OpticsKind kOptics, typename V>
VS_HOST_DEVICE inline void take_sample(const FrameView<V>& v, const Ray& ray, uint32_t region, float t, float end,
                                       float f, float len_ref, RayState<V>& s) {
  const bool iso = v.settings.iso_count > 0;
  if (iso && s.prev.valid) isosurfaces(v, ray, {s.prev.t, s.prev.f, t, f, s.prev.end, s.prev.region, region}, s);
  // Without isosurfaces the march stops at opacity before this sample; with them, a surface
  // just composited may have made the ray opaque.
  if ((!iso || !finished(v, s)) && owns(v, ray, t)) {
    if constexpr (kOptics == OpticsKind::blackbody) {
      const float temperature = sample(v.volume, 1, region, ray.at(t), s);
      ++s.samples;
      blackbody_step(v.optics.bb, f, temperature, len_ref, s.acc);
    } else {
      Rgba c = v.optics.tf.lookup(f);
      if (c.a > 0.f) {
        const float alpha = corrected_alpha(c.a, len_ref);
        if (v.settings.shade) {
          c = headlight(c, world_gradient(v, region, ray.at(t), f, s), ray.dir_w, 0.35f, 0.25f);
          s.samples += 6;
        }
        s.acc.blend_gray(c.r, c.g, c.b, alpha);
      }
    }
  }
  if (iso) s.prev = {true, t, f, region, end};  // only isosurfaces look back
}

// The steps of one interval (settings.h, March).
struct Steps {
  float t0, t1, dt, inv_ref;
  uint32_t n;
  March march;
  float first;  // lattice: the index of the interval's first lattice point
  // Sample k: its distance and the length of its step in reference steps.
  VS_FORCE_INLINE VS_HOST_DEVICE void at(uint32_t k, float jitter, float& t, float& len_ref) const {
    if (march != March::fixed_midpoint) {
      // Lattice: first + k is an exact integer, so a lattice point is the same float in every
      // interval that holds it.
      t = march == March::lattice ? (first + float(k) + jitter) * dt : t0 + (float(k) + jitter) * dt;
      len_ref = dt * inv_ref;
      return;
    }
    const float a = t0 + float(k) * dt;
    const float e = k + 1 < n ? a + dt : t1;
    t = 0.5f * (a + e);
    len_ref = (e - a) * inv_ref;
  }
};

VS_HOST_DEVICE inline uint32_t step_count(float steps) {  // no float->int overflow
  return steps < 1.f ? 1u : (steps < 16777216.f ? uint32_t(steps) : 16777216u);
}

// Lattice points in [t0, t1): m from ceil(t0 / dt - jitter) while (m + jitter) * dt < t1. None
// (n = 0) where the interval is shorter than a step and holds no point. False beyond 2^23 steps
// from the ray's origin, where floats no longer count steps exactly (the caller falls back).
VS_HOST_DEVICE inline bool lattice_steps(Steps& s, float jitter) {
  const float last = s.t1 / s.dt - jitter;
  if (!(last < 8388608.f)) return false;
  s.first = ceilf(s.t0 / s.dt - jitter);
  const float n = ceilf(last) - s.first;
  s.n = n > 0.f ? uint32_t(n) : 0u;
  return true;
}

VS_HOST_DEVICE inline Steps make_steps(const IntegratorSettings& st, const Ray& ray, float width, float t0, float t1,
                                       float jitter) {
  const float len = t1 - t0;
  const float max_dt = width / (st.rate * ray.dir_len);
  Steps s{t0, t1, max_dt, 1.f / st.ref_step, 1u, st.march, 0.f};
  if (s.march == March::lattice && lattice_steps(s, jitter)) return s;
  if (s.march == March::fixed_midpoint) {
    s.n = step_count(ceilf(len / max_dt * (1.f - 1e-5f)));  // a rounding remainder is no extra step
  } else {
    s.march = March::equal_jittered;
    s.n = step_count(ceilf(len / max_dt));
    s.dt = len / float(s.n);
  }
  return s;
}

// The steps of a region's interval: the region's own step width where sampling is adaptive.
template <typename V>
VS_HOST_DEVICE inline Steps interval_steps(const FrameView<V>& v, const Ray& ray, const RayInterval& iv, float jitter) {
  const float width = v.settings.adaptive ? v.volume.step_width(iv.region) : 1.f;
  return make_steps(v.settings, ray, width, iv.t0, iv.t1, jitter);
}

#if !defined(__CUDA_ARCH__)
// The CPU's march of transfer-function intervals without isosurfaces or shading, in batches of
// kSampleBatch samples: a batch's reconstructions, table lookups and opacity corrections do not
// depend on one another, so the core overlaps their long chains of dependent operations (and
// SIMD lanes take them); only compositing is serial. The same samples, colours, opacities and
// order as the one-by-one loop (take_sample), so the same image bit for bit; a ray that turns
// opaque inside a batch has computed up to kSampleBatch - 1 samples it does not use (and does
// not count). Volumes that sample a batch over several regions at once (AmrVolume: SIMD lanes,
// each with its own ABR) queue a ray's samples across intervals (trace_ray), so that batches fill
// also where intervals hold a sample or two (jet's small ABRs, 1.8 on average); other volumes
// batch intervals of kMinBatchSteps or more one by one and march shorter ones sample by sample.
inline constexpr uint32_t kSampleBatch = 8;
inline constexpr uint32_t kMinBatchSteps = 4;

struct SampleQueue {
  float t[kSampleBatch], len_ref[kSampleBatch];
  uint32_t region[kSampleBatch];
  uint32_t n = 0;
};

template <typename V>
concept SamplesAcrossRegions = requires(const V& volume, const uint32_t* regions, const vec3f& p, const float* t,
                                        float* out) {
  volume.sample_regions_batch(0, regions, p, p, t, 1u, out);
};

template <typename V>
inline bool batches_samples(const FrameView<V>& v) {
  return v.settings.cpu_batches && v.settings.iso_count == 0 && !v.settings.shade;
}

// Takes the queued samples and empties the queue; false once the ray is finished.
template <typename V>
inline bool take_queued(const FrameView<V>& v, const Ray& ray, SampleQueue& q, RayState<V>& s) {
  if (q.n == 0) return true;
  float f[kSampleBatch];
  if constexpr (SamplesAcrossRegions<V>) {
    v.volume.sample_regions_batch(0, q.region, ray.org, ray.dir, q.t, q.n, f);
  } else {
    for (uint32_t i = 0; i < q.n; ++i) f[i] = sample(v.volume, 0, q.region[i], ray.at(q.t[i]), s);
  }
  TfBatch c;
  tf_lookup_batch(v.optics.tf, f, q.len_ref, q.n, c);  // a NaN f (no data) is skipped below
  const uint32_t n = q.n;
  q.n = 0;
  for (uint32_t i = 0; i < n; ++i) {
    ++s.samples;
    if (is_nan(f[i]) || !(c.a[i] > 0.f) || !owns(v, ray, q.t[i])) continue;
    s.acc.blend_gray(c.r[i], c.g[i], c.b[i], c.alpha[i]);
    if (finished(v, s)) return false;
  }
  return true;
}

// Queues an interval's steps, taking each full batch; false once the ray is finished.
template <typename V>
inline bool queue_steps(const FrameView<V>& v, const Ray& ray, uint32_t region, const Steps& steps, float jitter,
                        SampleQueue& q, RayState<V>& s) {
  for (uint32_t k = 0; k < steps.n; ++k) {
    steps.at(k, jitter, q.t[q.n], q.len_ref[q.n]);
    q.region[q.n] = region;
    if (++q.n == kSampleBatch && !take_queued(v, ray, q, s)) return false;
  }
  return true;
}

template <typename V>
inline void march_interval_batched(const FrameView<V>& v, const Ray& ray, const RayInterval& iv, const Steps& steps,
                                   float jitter, RayState<V>& s) {
  SampleQueue q;
  if (queue_steps(v, ray, iv.region, steps, jitter, q, s)) take_queued(v, ray, q, s);
}

// A ray's interval into the queue (trace_ray); one of kMinBatchSteps or more in batches of its
// own (the queue taken before and after it), which share a region: the one-ABR batch sampler.
template <typename V>
inline bool queue_interval(const FrameView<V>& v, const Ray& ray, const RayInterval& iv, float jitter, SampleQueue& q,
                           RayState<V>& s) {
  if (!(iv.t1 - iv.t0 > 0.f)) return true;
  const Steps steps = interval_steps(v, ray, iv, jitter);
  const bool alone = steps.n >= kMinBatchSteps;
  if (alone && !take_queued(v, ray, q, s)) return false;
  if (!queue_steps(v, ray, iv.region, steps, jitter, q, s)) return false;
  return !alone || take_queued(v, ray, q, s);
}
#endif

// Marches one region's interval.
template <OpticsKind kOptics, typename V>
VS_HOST_DEVICE inline void march_interval(const FrameView<V>& v, const Ray& ray, const RayInterval& iv, float jitter,
                                          RayState<V>& s) {
  const IntegratorSettings& st = v.settings;
  if (!(iv.t1 - iv.t0 > 0.f)) return;
  const Steps steps = interval_steps(v, ray, iv, jitter);
#if !defined(__CUDA_ARCH__)
  if constexpr (kOptics == OpticsKind::tf) {
    // Volumes without batches across regions (meshes): short intervals are marched one by one.
    if (batches_samples(v) && steps.n >= kMinBatchSteps) {
      march_interval_batched(v, ray, iv, steps, jitter, s);
      return;
    }
  }
#endif
  if (st.iso_count > 0) {
    if (s.prev.valid && iv.t0 - s.prev.end > 1e-4f * steps.dt) close_interval(v, ray, s);
    if (!s.prev.valid) {  // start the crossing test at the interval's entry face (just inside)
      const float t0 = iv.t0 + kFaceInset * steps.dt;
      const float f0 = sample(v.volume, 0, iv.region, ray.at(t0), s);
      ++s.samples;
      if (!is_nan(f0)) s.prev = {true, t0, f0, iv.region, iv.t1};
    }
  }
  for (uint32_t k = 0; k < steps.n; ++k) {
    float t, len_ref;
    steps.at(k, jitter, t, len_ref);
    const float f = sample(v.volume, 0, iv.region, ray.at(t), s);
    ++s.samples;
    if (is_nan(f)) {  // outside the volume's data (e.g. beyond every cell's support)
      s.prev.valid = false;
      continue;
    }
    take_sample<kOptics>(v, ray, iv.region, t, iv.t1, f, len_ref, s);
    if (finished(v, s)) return;
  }
}

// kOptics: the frame's optics as a template argument (one branch per ray, not per sample).
template <OpticsKind kOptics, typename V>
VS_HOST_DEVICE inline RayState<V> trace_ray(const FrameView<V>& v, const vec3f& org_w, const vec3f& dir_w,
                                            float jitter) {
  Ray ray;
  ray.org_w = org_w;
  ray.dir_w = dir_w;
  ray.org = (org_w - v.grid.origin) * v.grid.inv_cell_size;
  ray.dir = dir_w * v.grid.inv_cell_size;
  ray.dir_len = length(ray.dir);
  ray.clipped = !owns_everything(v);
  RayState<V> s;
#if !defined(__CUDA_ARCH__)
  if constexpr (kOptics == OpticsKind::tf && SamplesAcrossRegions<V>) {
    if (batches_samples(v)) {
      SampleQueue q;
      v.volume.for_each_interval(ray.org, ray.dir,
                                 [&](const RayInterval& iv) { return queue_interval(v, ray, iv, jitter, q, s); });
      take_queued(v, ray, q, s);
      return s;
    }
  }
#endif
  v.volume.for_each_interval(ray.org, ray.dir, [&](const RayInterval& iv) {
    march_interval<kOptics>(v, ray, iv, jitter, s);
    return !finished(v, s);
  });
  if (v.settings.iso_count > 0 && !finished(v, s)) close_interval(v, ray, s);
  return s;
}

}  // namespace detail

// Renders pixel (x, y) into v.rgba (and v.sample_counts when given) with the frame's optics
// (v.optics.kind == kOptics): launches pick the instantiation once per frame. Returns the
// samples taken (the CPU launch sums them without a per-pixel buffer).
template <OpticsKind kOptics, typename V>
VS_HOST_DEVICE inline uint32_t render_pixel(const FrameView<V>& v, uint32_t x, uint32_t y) {
  const IntegratorSettings& st = v.settings;
  const uint32_t spp = st.spp > 0 ? st.spp : 1u;
  const uint32_t pixel = y * v.width + x;
  // Per-pixel random offsets, shifted per ray by low-discrepancy sequences (R2 on the pixel,
  // golden ratio in depth), so several rays per pixel stratify instead of clumping.
  const float rx = detail::hash_unit(x, y, st.seed * 3u + 1u), ry = detail::hash_unit(x, y, st.seed * 3u + 2u);
  const float rz = detail::hash_unit(x, y, st.seed * 3u + 3u);
  vec3f color{0.f, 0.f, 0.f};
  float alpha = 0.f;
  uint32_t samples = 0;
  for (uint32_t i = 0; i < spp; ++i) {
    const float sx = spp > 1 ? detail::fract(rx + 0.7548776662f * float(i)) : 0.5f;
    const float sy = spp > 1 ? detail::fract(ry + 0.5698402910f * float(i)) : 0.5f;
    float jitter = st.jitter ? detail::fract(rz + 0.6180339887f * float(i)) : 0.5f;
    jitter = kFaceInset + (1.f - 2.f * kFaceInset) * jitter;  // never exactly on a region face
    vec3f org, dir;
    v.camera.ray(float(x) + sx, float(y) + sy, org, dir);
    const detail::RayState<V> s = detail::trace_ray<kOptics>(v, org, dir, jitter);
    color = color + s.acc.color;
    alpha += s.acc.alpha();
    samples += s.samples;
  }
  const float inv = 1.f / float(spp);
  float* out = v.rgba + 4 * size_t(pixel);
  out[0] = color.x * inv;
  out[1] = color.y * inv;
  out[2] = color.z * inv;
  out[3] = alpha * inv;
  if (v.sample_counts) v.sample_counts[pixel] = samples;
  return samples;
}

// Calls f with the frame's optics as a template argument: f(std::integral_constant<OpticsKind, K>).
template <typename V, typename F>
VS_HOST_DEVICE inline void with_optics(const FrameView<V>& v, F&& f) {
  if (v.optics.kind == OpticsKind::blackbody)
    f(std::integral_constant<OpticsKind, OpticsKind::blackbody>{});
  else
    f(std::integral_constant<OpticsKind, OpticsKind::tf>{});
}

}  // namespace vs
