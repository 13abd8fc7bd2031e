// The block raycaster of paper 004 (Sect. 4.2), one per-pixel function for CPU and CUDA.
//
// A ray visits the kd-tree's blocks front to back and marches each block's segment with a step
// adapted to the block's level (cell width / rate); colour and opacity carry over from block to
// block (front-to-back blending). Opacity is corrected for the true length of every step,
// alpha' = 1 - (1 - alpha)^(dt / dt_ref) (paper Eq. 1 for any step ratio), so the last, shorter
// step of each segment is exact too. Samples sit at the middle of their step.
//
// Reconstruction: nearest (the value of the cell containing the sample) or trilinear. Trilinear
// interpolates the vertex values of vertex_field.h (shared by neighbouring blocks, dangling nodes
// fixed up) when the view has them; without them it falls back to interpolating between the cell
// centres of the sample's brick, clamped at the brick's faces (seams between bricks).
#pragma once
#include <cmath>
#include <cstdint>

#include "volstream/blocks/blackbody.h"
#include "volstream/blocks/kd_blocks.h"
#include "volstream/blocks/vertex_field.h"
#include "volstream/render/camera.h"
#include "volstream/render/integrator.h"
#include "volstream/render/transfer_function.h"

namespace vs {

enum class Reconstruction : uint32_t { nearest = 0, trilinear = 1 };
enum class Optics : uint32_t { tf = 0, blackbody = 1 };

struct BlockSettings {
  float rate = 2.f;      // samples per cell width of each block's level
  float ref_step = 1.f;  // world length over which table alphas / coefficients apply unchanged
  Reconstruction reconstruction = Reconstruction::trilinear;
  Optics optics = Optics::tf;
};

// Pointers and the element counts behind them (the counts are for copying the arrays to the GPU;
// kernels do not read them). Tables: tf.size and bb.size entries.
struct BlockRenderView {
  KdView kd;                           // kd.node_count nodes, kd.block_count blocks
  const Brick* bricks = nullptr;
  uint32_t brick_count = 0;
  const float* values = nullptr;       // primary field (density for blackbody), device order
  const float* temperature = nullptr;  // blackbody only
  uint64_t value_count = 0;            // cells in values (and temperature)
  const uint64_t* vertex_offsets = nullptr;   // trilinear: per block (vertex_field.h); null: per-brick fallback
  const float* vertex_values = nullptr;
  const float* vertex_temperature = nullptr;
  uint64_t vertex_count = 0;           // entries of vertex_values (and vertex_temperature)
  TfView tf;
  BlackbodyView bb;
  CameraView camera;
  GridMap grid;
  BlockSettings settings;
  uint32_t width = 0, height = 0;
  float* rgba = nullptr;               // output: premultiplied linear RGBA
  uint32_t* sample_counts = nullptr;   // optional
};

namespace blocks {

VS_HOST_DEVICE inline int32_t clampi(int32_t v, int32_t lo, int32_t hi) { return v < lo ? lo : (v > hi ? hi : v); }

VS_HOST_DEVICE inline float cell_value(const float* values, const Brick& br, int32_t x, int32_t y, int32_t z) {
  return values[br.value_offset + (uint64_t(z) * uint64_t(br.dims.y) + uint64_t(y)) * uint64_t(br.dims.x) + uint64_t(x)];
}

// Value of the block's cell containing p (grid units); clamped to the block against rounding.
VS_HOST_DEVICE inline float sample_nearest(const float* values, const Brick& br, const Block& b, const vec3f& p) {
  const float inv_w = 1.f / float(br.width());
  int32_t c[3];
  for (int a = 0; a < 3; ++a) {
    const int32_t hi = (b.box.upper[a] - br.lower[a]) / br.width() - 1;
    c[a] = clampi(int32_t(floorf((p[a] - float(br.lower[a])) * inv_w)), b.cell_lo[a], hi);
  }
  return cell_value(values, br, c[0], c[1], c[2]);
}

// Trilinear between the cell centres of the brick (across the kd planes that cut it), clamped
// to the outermost centres at the brick's faces.
VS_HOST_DEVICE inline float sample_trilinear(const float* values, const Brick& br, const vec3f& p) {
  const float inv_w = 1.f / float(br.width());
  int32_t i0[3], i1[3];
  float f[3];
  for (int a = 0; a < 3; ++a) {
    const float n = float(br.dims[a] - 1);
    float u = (p[a] - float(br.lower[a])) * inv_w - 0.5f;
    u = u > 0.f ? (u < n ? u : n) : 0.f;
    i0[a] = clampi(int32_t(u), 0, br.dims[a] - 1);
    i1[a] = i0[a] + 1 < br.dims[a] ? i0[a] + 1 : i0[a];
    f[a] = u - float(i0[a]);
  }
  auto at = [&](int dx, int dy, int dz) {
    return cell_value(values, br, dx ? i1[0] : i0[0], dy ? i1[1] : i0[1], dz ? i1[2] : i0[2]);
  };
  const float x00 = at(0, 0, 0) + (at(1, 0, 0) - at(0, 0, 0)) * f[0];
  const float x10 = at(0, 1, 0) + (at(1, 1, 0) - at(0, 1, 0)) * f[0];
  const float x01 = at(0, 0, 1) + (at(1, 0, 1) - at(0, 0, 1)) * f[0];
  const float x11 = at(0, 1, 1) + (at(1, 1, 1) - at(0, 1, 1)) * f[0];
  const float y0 = x00 + (x10 - x00) * f[1], y1 = x01 + (x11 - x01) * f[1];
  return y0 + (y1 - y0) * f[2];
}

VS_HOST_DEVICE inline float sample_block(const BlockRenderView& v, const float* cells, const float* vertices,
                                         uint32_t block, const vec3f& p) {
  const Block& b = v.kd.blocks[block];
  const Brick& br = v.bricks[b.brick];
  if (v.settings.reconstruction == Reconstruction::nearest) return sample_nearest(cells, br, b, p);
  if (vertices && v.vertex_offsets) return sample_vertices(vertices, v.vertex_offsets[block], b, p);
  return sample_trilinear(cells, br, p);
}

// Accumulated light along the ray: premultiplied colour and per-channel transmittance (the
// blackbody model absorbs each channel differently; the TF model keeps the three equal).
struct Accum {
  vec3f color{0.f, 0.f, 0.f};
  vec3f trans{1.f, 1.f, 1.f};
  uint32_t samples = 0;
  VS_HOST_DEVICE float alpha() const { return 1.f - (trans.x + trans.y + trans.z) * (1.f / 3.f); }
  // Early ray termination at alpha 0.99 in every channel.
  VS_HOST_DEVICE bool opaque() const {
    const float t = trans.x > trans.y ? (trans.x > trans.z ? trans.x : trans.z) : (trans.y > trans.z ? trans.y : trans.z);
    return t <= 1.f - kOpaque;
  }
};

// Transfer function: alpha' = 1 - (1 - alpha)^(len / ref), front-to-back blending.
VS_HOST_DEVICE inline void shade_tf(const BlockRenderView& v, float f, float len_ref, Accum& acc) {
  const Rgba c = v.tf.lookup(f);
  if (!(c.a > 0.f)) return;
  const float alpha = c.a >= 1.f ? 1.f : 1.f - exp2f(len_ref * log2f(1.f - c.a));
  const float t = acc.trans.x;
  acc.color = acc.color + vec3f(c.r, c.g, c.b) * (t * alpha);
  acc.trans = vec3f(t * (1.f - alpha));
}

// Emission-absorption over a homogeneous step of len_ref reference steps, per channel:
// dI = T * E * (1 - exp(-k len)) / k, T *= exp(-k len). exp(-k len) is the same opacity
// correction as above with alpha_ref = 1 - exp(-k).
VS_HOST_DEVICE inline void shade_blackbody(const BlockRenderView& v, float rho, float temperature, float len_ref,
                                           Accum& acc) {
  const BlackbodyView& bb = v.bb;
  const float rn = bb.normalised_density(rho);
  if (!(rn > 0.f)) return;
  const float re = bb.emission_power == 1.f ? rn : powf(rn, bb.emission_power);
  const vec3f e = bb.color(temperature) * (bb.emission * re);
  for (int c = 0; c < 3; ++c) {
    const float k = bb.absorption * rn * bb.rayleigh[c];
    const float x = k * len_ref;
    const float tr = expf(-x);
    const float path = x > 1e-4f ? (1.f - tr) / k : len_ref;  // integral of exp(-k s) over the step
    acc.color[c] += acc.trans[c] * e[c] * path;
    acc.trans[c] *= tr;
  }
}

// Marches the block's segment [t0, t1] with steps of the block's cell width / rate; the last step
// is shortened to end exactly at t1 and its opacity uses that true length.
VS_HOST_DEVICE inline void march_block(const BlockRenderView& v, const detail::Ray& ray, uint32_t block, float t0,
                                       float t1, Accum& acc) {
  const Block& b = v.kd.blocks[block];
  const float len = t1 - t0;
  if (!(len > 0.f)) return;
  const float dt = float(level_width(b.level)) / (v.settings.rate * ray.dir_len);
  const float inv_ref = 1.f / v.settings.ref_step;
  const float steps = ceilf(len / dt * (1.f - 1e-5f));  // a rounding remainder is no extra step
  const uint32_t n = steps < 1.f ? 1u : uint32_t(steps);
  for (uint32_t k = 0; k < n && !acc.opaque(); ++k) {
    const float a = t0 + float(k) * dt;
    const float e = k + 1 < n ? a + dt : t1;
    const float step = e - a;
    const vec3f p = ray.at(0.5f * (a + e));
    const float f = sample_block(v, v.values, v.vertex_values, block, p);
    ++acc.samples;
    if (v.settings.optics == Optics::blackbody) {
      const float temp = sample_block(v, v.temperature, v.vertex_temperature, block, p);
      ++acc.samples;
      shade_blackbody(v, f, temp, step * inv_ref, acc);
    } else {
      shade_tf(v, f, step * inv_ref, acc);
    }
  }
}

VS_HOST_DEVICE inline Accum trace_blocks(const BlockRenderView& v, const vec3f& org_w, const vec3f& dir_w) {
  detail::Ray ray;
  ray.org_w = org_w;
  ray.dir_w = dir_w;
  ray.org = (org_w - v.grid.origin) * v.grid.inv_cell_size;
  ray.dir = dir_w * v.grid.inv_cell_size;
  ray.dir_len = length(ray.dir);
  Accum acc;
  kd_traverse(v.kd, ray.org, ray.dir, 0.f, INFINITY, [&](uint32_t block, float t0, float t1) {
    march_block(v, ray, block, t0, t1, acc);
    return !acc.opaque();
  });
  return acc;
}

}  // namespace blocks

// Renders pixel (x, y) (one ray through its centre) into v.rgba.
VS_HOST_DEVICE inline void render_block_pixel(const BlockRenderView& v, uint32_t x, uint32_t y) {
  vec3f org, dir;
  v.camera.ray(float(x) + 0.5f, float(y) + 0.5f, org, dir);
  const blocks::Accum acc = blocks::trace_blocks(v, org, dir);
  float* out = v.rgba + 4 * (size_t(y) * v.width + x);
  out[0] = acc.color.x;
  out[1] = acc.color.y;
  out[2] = acc.color.z;
  out[3] = acc.alpha();
  if (v.sample_counts) v.sample_counts[size_t(y) * v.width + x] = acc.samples;
}

}  // namespace vs
