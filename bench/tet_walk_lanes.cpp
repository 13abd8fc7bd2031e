// Would rays in SIMD lanes pay for the tet walk on this CPU? The CPU renderer walks one ray at a
// time through the tets' walk records (umesh/element_bvh.h): per sample, record tests until the
// tet holding the sample, then its four corners' values. This driver walks the same rays that way
// and eight at a time in AVX2 lanes (a record's 12 floats, its neighbour and the corners' values
// by gathers; a lane whose ray is done takes the next one) and four at a time on scalar registers
// (walk_interleaved), checks that all give the same per-ray sums of the sampled values, and prints
// nanoseconds per record test of each.
// The rays (make_rays: a grid of width x width parallel rays, in the renderer's tile order) take
// up to `samples` steps of `step` times the mean tet box width, and stop at the mesh's boundary or
// where a sample's walk takes more than UMeshView::kMaxWalk tests (where the renderer would search
// the BVH instead). One thread each way.
// usage: volstream_bench_tet_walk [--elements N] [--width W] [--samples K] [--step S] [--repeats N]
#include <immintrin.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "volstream/core/simd.h"
#include "volstream/umesh/demo.h"
#include "volstream/umesh/element_bvh.h"
#include "volstream/umesh/from_mesh_data.h"
#include "volstream/umesh/mesh_accel.h"

namespace {

using vs::vec3f;

struct Options {
  uint64_t elements = 1000000;
  int width = 512, samples = 400, repeats = 5;
  float step = 0.5f;
};

struct Rays {
  std::vector<vec3f> origin, dir;
  std::vector<uint32_t> start;  // the tet holding the origin
};

struct Walked {
  std::vector<float> sums;  // per ray: the sum of its samples' values
  uint64_t tests = 0;       // record tests
};

constexpr uint32_t kNone = vs::UMeshView::kNoNeighborIndex;

// The renderer's walk (UMeshView::record_step), one ray after the other.
Walked walk_scalar(const vs::UMeshView& m, const float* values, const Rays& rays, int samples, float dt) {
  Walked out{std::vector<float>(rays.start.size(), 0.f), 0};
  for (size_t r = 0; r < rays.start.size(); ++r) {
    uint32_t e = rays.start[r];
    float sum = 0.f;
    for (int k = 0; k < samples && e != kNone; ++k) {
      const vec3f p = rays.origin[r] + rays.dir[r] * (float(k) * dt);
      float w[4];
      bool inside = false;
      for (int walked = 0; !inside && e != kNone && walked < vs::UMeshView::kMaxWalk; ++walked) {
        ++out.tests;
        inside = m.record_step(e, p, w);
      }
      if (!inside) break;
      const uint32_t* v = m.elements[e].v;
      sum += w[0] * values[v[0]] + w[1] * values[v[1]] + w[2] * values[v[2]] + w[3] * values[v[3]];
    }
    out.sums[r] = sum;
  }
  return out;
}

// Four rays at a time on scalar registers, one record test each per round, as walk_scalar tests
// them: the four chains of dependent loads and arithmetic do not depend on one another, so the core
// can overlap them where one ray's chain alone leaves it waiting.
Walked walk_interleaved(const vs::UMeshView& m, const float* values, const Rays& rays, int samples, float dt) {
  constexpr int kRays = 4;
  struct Walk {
    size_t ray = 0;
    uint32_t e = 0;
    int k = 0, walked = 0;
    float sum = 0.f;
    bool active = false;
  };
  Walked out{std::vector<float>(rays.start.size(), 0.f), 0};
  size_t next = 0;
  const auto take_next = [&](Walk& w) {
    w.active = next < rays.start.size();
    if (w.active) w = {next, rays.start[next], 0, 0, 0.f, true}, ++next;
  };
  const auto finish = [&](Walk& w) {
    out.sums[w.ray] = w.sum;
    take_next(w);
  };
  Walk walks[kRays];
  for (Walk& w : walks) take_next(w);
  for (bool any = true; any;) {
    any = false;
    for (Walk& w : walks) {
      if (!w.active) continue;
      any = true;
      ++out.tests;
      const vec3f p = rays.origin[w.ray] + rays.dir[w.ray] * (float(w.k) * dt);
      float weight[4];
      if (m.record_step(w.e, p, weight)) {
        const uint32_t* v = m.elements[w.e].v;
        w.sum +=
            weight[0] * values[v[0]] + weight[1] * values[v[1]] + weight[2] * values[v[2]] + weight[3] * values[v[3]];
        w.walked = 0;
        if (++w.k == samples) finish(w);
      } else if (w.e == kNone || ++w.walked == vs::UMeshView::kMaxWalk) {
        finish(w);
      }
    }
  }
  return out;
}

// Eight rays in AVX2 lanes, the same arithmetic per lane as record_step and tet_weights_of.
struct Lanes {
  __m256 ox, oy, oz, dx, dy, dz, sum;
  __m256i e, k, walked, ray;  // ray -1: the lane is idle
};

__attribute__((target("avx2"))) inline __m256 gather_f(const float* base, __m256i index) {
  return _mm256_i32gather_ps(base, index, 4);
}
__attribute__((target("avx2"))) inline __m256i gather_i(const uint32_t* base, __m256i index) {
  return _mm256_i32gather_epi32(reinterpret_cast<const int*>(base), index, 4);
}

// Lanes whose ray is done store its sum and take the next ray (none left: idle).
__attribute__((target("avx2"))) void refill(Lanes& l, __m256i done, const Rays& rays, size_t& next,
                                            std::vector<float>& sums) {
  alignas(32) float f[7][8];
  alignas(32) int32_t i[5][8];
  _mm256_store_ps(f[0], l.ox), _mm256_store_ps(f[1], l.oy), _mm256_store_ps(f[2], l.oz);
  _mm256_store_ps(f[3], l.dx), _mm256_store_ps(f[4], l.dy), _mm256_store_ps(f[5], l.dz);
  _mm256_store_ps(f[6], l.sum);
  _mm256_store_si256(reinterpret_cast<__m256i*>(i[0]), l.e);
  _mm256_store_si256(reinterpret_cast<__m256i*>(i[1]), l.k);
  _mm256_store_si256(reinterpret_cast<__m256i*>(i[2]), l.ray);
  _mm256_store_si256(reinterpret_cast<__m256i*>(i[3]), done);
  _mm256_store_si256(reinterpret_cast<__m256i*>(i[4]), l.walked);
  for (int lane = 0; lane < 8; ++lane) {
    if (!i[3][lane]) continue;
    if (i[2][lane] >= 0) sums[size_t(i[2][lane])] = f[6][lane];
    if (next == rays.start.size()) {
      i[2][lane] = -1;
      continue;
    }
    const size_t r = next++;
    f[0][lane] = rays.origin[r].x, f[1][lane] = rays.origin[r].y, f[2][lane] = rays.origin[r].z;
    f[3][lane] = rays.dir[r].x, f[4][lane] = rays.dir[r].y, f[5][lane] = rays.dir[r].z;
    f[6][lane] = 0.f;
    i[0][lane] = int32_t(rays.start[r]), i[1][lane] = 0, i[2][lane] = int32_t(r), i[4][lane] = 0;
  }
  l.ox = _mm256_load_ps(f[0]), l.oy = _mm256_load_ps(f[1]), l.oz = _mm256_load_ps(f[2]);
  l.dx = _mm256_load_ps(f[3]), l.dy = _mm256_load_ps(f[4]), l.dz = _mm256_load_ps(f[5]);
  l.sum = _mm256_load_ps(f[6]);
  l.e = _mm256_load_si256(reinterpret_cast<const __m256i*>(i[0]));
  l.k = _mm256_load_si256(reinterpret_cast<const __m256i*>(i[1]));
  l.ray = _mm256_load_si256(reinterpret_cast<const __m256i*>(i[2]));
  l.walked = _mm256_load_si256(reinterpret_cast<const __m256i*>(i[4]));
}

__attribute__((target("avx2"))) Walked walk_lanes(const vs::UMeshView& m, const float* values, const Rays& rays,
                                                  int samples, float dt) {
  Walked out{std::vector<float>(rays.start.size(), 0.f), 0};
  const float* rec = reinterpret_cast<const float*>(m.tet_walk);
  const uint32_t* rec_i = reinterpret_cast<const uint32_t*>(m.tet_walk);
  const uint32_t* corners = m.elements[0].v;
  Lanes l{};
  l.ray = _mm256_set1_epi32(-1);
  size_t next = 0;
  refill(l, _mm256_set1_epi32(-1), rays, next, out.sums);
  const __m256i none = _mm256_set1_epi32(int32_t(kNone));
  const __m256i all_samples = _mm256_set1_epi32(samples), max_walk = _mm256_set1_epi32(vs::UMeshView::kMaxWalk);
  const __m256 one = _mm256_set1_ps(1.f), step = _mm256_set1_ps(dt);
  uint64_t tests = 0;
  for (;;) {
    const __m256i active = _mm256_cmpgt_epi32(l.ray, _mm256_set1_epi32(-1));
    const int active_mask = _mm256_movemask_ps(_mm256_castsi256_ps(active));
    if (active_mask == 0) break;
    tests += uint64_t(__builtin_popcount(unsigned(active_mask)));
    const __m256i e = _mm256_and_si256(l.e, active);  // idle lanes read record 0
    const __m256i base = _mm256_slli_epi32(e, 4);     // 16 floats a record
    const __m256 t = _mm256_mul_ps(_mm256_cvtepi32_ps(l.k), step);
    const __m256 bx = _mm256_sub_ps(_mm256_add_ps(l.ox, _mm256_mul_ps(l.dx, t)), gather_f(rec, base));
    const __m256 by = _mm256_sub_ps(_mm256_add_ps(l.oy, _mm256_mul_ps(l.dy, t)),
                                    gather_f(rec, _mm256_add_epi32(base, _mm256_set1_epi32(1))));
    const __m256 bz = _mm256_sub_ps(_mm256_add_ps(l.oz, _mm256_mul_ps(l.dz, t)),
                                    gather_f(rec, _mm256_add_epi32(base, _mm256_set1_epi32(2))));
    __m256 w[4];
    for (int row = 0; row < 3; ++row) {
      const __m256i at = _mm256_add_epi32(base, _mm256_set1_epi32(3 + 3 * row));
      const __m256 rx = gather_f(rec, at), ry = gather_f(rec, _mm256_add_epi32(at, _mm256_set1_epi32(1))),
                   rz = gather_f(rec, _mm256_add_epi32(at, _mm256_set1_epi32(2)));
      w[row + 1] = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(bx, rx), _mm256_mul_ps(by, ry)), _mm256_mul_ps(bz, rz));
    }
    w[0] = _mm256_sub_ps(_mm256_sub_ps(_mm256_sub_ps(one, w[1]), w[2]), w[3]);
    // tet_weights_of's tournament: the first smallest weight names the face to cross
    const __m256 low_1 = _mm256_cmp_ps(w[1], w[0], _CMP_LT_OQ), low_3 = _mm256_cmp_ps(w[3], w[2], _CMP_LT_OQ);
    const __m256 least_01 = _mm256_blendv_ps(w[0], w[1], low_1), least_23 = _mm256_blendv_ps(w[2], w[3], low_3);
    const __m256 pick_23 = _mm256_cmp_ps(least_23, least_01, _CMP_LT_OQ);
    const __m256i face_01 = _mm256_and_si256(_mm256_castps_si256(low_1), _mm256_set1_epi32(1));
    const __m256i face_23 =
        _mm256_add_epi32(_mm256_set1_epi32(2), _mm256_and_si256(_mm256_castps_si256(low_3), _mm256_set1_epi32(1)));
    const __m256i face =
        _mm256_castps_si256(_mm256_blendv_ps(_mm256_castsi256_ps(face_01), _mm256_castsi256_ps(face_23), pick_23));
    const __m256 least = _mm256_blendv_ps(least_01, least_23, pick_23);
    const __m256i inside =
        _mm256_and_si256(_mm256_castps_si256(_mm256_cmp_ps(least, _mm256_setzero_ps(), _CMP_GE_OQ)), active);
    // Inside: the sample's value, then the next sample.
    if (!_mm256_testz_si256(inside, inside)) {
      const __m256i v = _mm256_slli_epi32(e, 3);  // 8 corner indices an element
      __m256 f = _mm256_setzero_ps();
      for (int c = 0; c < 4; ++c) {
        const __m256i corner = gather_i(corners, _mm256_add_epi32(v, _mm256_set1_epi32(c)));
        const __m256 value =
            _mm256_mask_i32gather_ps(_mm256_setzero_ps(), values, corner, _mm256_castsi256_ps(inside), 4);
        f = c == 0 ? _mm256_mul_ps(w[0], value) : _mm256_add_ps(f, _mm256_mul_ps(w[c], value));
      }
      l.sum = _mm256_blendv_ps(l.sum, _mm256_add_ps(l.sum, f), _mm256_castsi256_ps(inside));
      l.k = _mm256_sub_epi32(l.k, inside);  // inside is -1
    }
    l.walked = _mm256_andnot_si256(inside, _mm256_sub_epi32(l.walked, active));  // tests of this sample
    // Outside: across the face.
    const __m256i outside = _mm256_andnot_si256(inside, active);
    const __m256i neighbour = gather_i(rec_i, _mm256_add_epi32(base, _mm256_add_epi32(face, _mm256_set1_epi32(12))));
    l.e = _mm256_blendv_epi8(l.e, neighbour, outside);
    const __m256i left = _mm256_and_si256(outside, _mm256_cmpeq_epi32(l.e, none));
    const __m256i too_far = _mm256_and_si256(outside, _mm256_cmpeq_epi32(l.walked, max_walk));
    const __m256i done =
        _mm256_or_si256(_mm256_or_si256(left, too_far), _mm256_and_si256(active, _mm256_cmpeq_epi32(l.k, all_samples)));
    if (!_mm256_testz_si256(done, done)) refill(l, done, rays, next, out.sums);
  }
  out.tests = tests;
  return out;
}

// A 2-D grid of parallel rays across the mesh's box, in the direction of the VTK comparison's
// camera (bench/umesh_vs_vtk.sh), ordered in 8x8 tiles as the CPU renderer takes them
// (launch_cpu.h), so that neighbouring rays cross the same tets; each starts just inside the box,
// in the tet that the element BVH finds there (rays whose start is in no tet are left out).
Rays make_rays(const vs::UMeshView& located, const vs::box3f& box, int width) {
  const vec3f dir = vs::normalize(vec3f(-1.8f, -1.1f, -2.4f));
  const vec3f u = vs::normalize(vs::cross(dir, vec3f(0.f, 1.f, 0.f)));
  const vec3f v = vs::cross(u, dir);
  const vec3f centre = box.center(), size = box.size();
  const float radius = 0.5f * std::sqrt(vs::dot(size, size));
  Rays rays;
  constexpr int kTile = 8;
  for (int ty = 0; ty < width; ty += kTile)
    for (int tx = 0; tx < width; tx += kTile)
      for (int y = ty; y < std::min(ty + kTile, width); ++y)
        for (int x = tx; x < std::min(tx + kTile, width); ++x) {
          const float a = radius * (2.f * (float(x) + 0.5f) / float(width) - 1.f);
          const float b = radius * (2.f * (float(y) + 0.5f) / float(width) - 1.f);
          const vec3f far = centre + u * a + v * b - dir * (2.f * radius);
          // entry into the box (slabs), then a hundredth of the box inside
          float t0 = 0.f, t1 = INFINITY;
          for (int axis = 0; axis < 3; ++axis) {
            const float lo = (box.lower[axis] - far[axis]) / dir[axis], hi = (box.upper[axis] - far[axis]) / dir[axis];
            t0 = std::max(t0, std::min(lo, hi)), t1 = std::min(t1, std::max(lo, hi));
          }
          if (!(t0 < t1)) continue;
          const vec3f start = far + dir * (t0 + 0.01f * radius);
          const int64_t e = located.locate(start).element;
          if (e < 0) continue;
          rays.origin.push_back(start), rays.dir.push_back(dir), rays.start.push_back(uint32_t(e));
        }
  return rays;
}

float mean_box_width(const vs::UMesh& mesh) {
  double sum = 0.0;
  const std::vector<vs::box3f> boxes = vs::element_boxes(mesh);
  for (const vs::box3f& b : boxes) {
    const vec3f s = b.size();
    sum += std::cbrt(double(s.x) * s.y * s.z);
  }
  return float(sum / double(boxes.size()));
}

double seconds_of(const std::function<void()>& run) {
  const auto start = std::chrono::steady_clock::now();
  run();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Options parse(int argc, char** argv) {
  Options o;
  if (argc % 2 == 0) throw std::invalid_argument(std::string("option ") + argv[argc - 1] + " has no value");
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    const char* value = argv[i + 1];
    if (key == "--elements")
      o.elements = uint64_t(std::atof(value));
    else if (key == "--width")
      o.width = std::atoi(value);
    else if (key == "--samples")
      o.samples = std::atoi(value);
    else if (key == "--step")
      o.step = float(std::atof(value));
    else if (key == "--repeats")
      o.repeats = std::atoi(value);
    else
      throw std::invalid_argument("unknown option " + key);
  }
  if (o.width < 1 || o.samples < 1 || o.repeats < 1 || !(o.step > 0.f))
    throw std::invalid_argument("--width, --samples, --repeats and --step must be positive");
  return o;
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  if (!vs::simd::use_avx2()) throw std::runtime_error("this CPU has no AVX2");
  const vs::MeshData data = vs::make_mesh_demo({"tets", o.elements, 1}, 0);
  const vs::UMesh mesh = vs::make_umesh(data, vs::mesh_transform(data), "demo");
  const vs::MeshAccel accel = vs::build_mesh_accel(mesh);
  const vs::TetWalkRecords records = vs::tet_walk_records(mesh, accel.neighbors);
  std::vector<float> values;
  for (const vs::MeshFieldRef& f : vs::mesh_fields(data))
    if (f.name == "density") values = vs::mesh_field_values(data, f);
  vs::UMeshView view;
  view.vertices = mesh.vertices.data();
  view.elements = mesh.elements.data();
  view.neighbors = accel.neighbors.data();
  view.tet_walk = records.data();
  vs::box3f box = vs::box3f::make_empty();
  for (const vec3f& x : mesh.vertices) box.extend(x);
  const Rays rays = make_rays(vs::view_of(mesh, accel), box, o.width);
  const float dt = o.step * mean_box_width(mesh);

  // The three walks in turn, round after round, so that a slow stretch of a shared machine
  // falls on all three; each round's time ratios, then their medians.
  Walked scalar, lanes, interleaved;
  std::vector<double> t_scalar, t_lanes, t_interleaved, lanes_gain, interleaved_gain;
  for (int round = 0; round < o.repeats; ++round) {
    t_scalar.push_back(seconds_of([&] { scalar = walk_scalar(view, values.data(), rays, o.samples, dt); }));
    t_lanes.push_back(seconds_of([&] { lanes = walk_lanes(view, values.data(), rays, o.samples, dt); }));
    t_interleaved.push_back(
        seconds_of([&] { interleaved = walk_interleaved(view, values.data(), rays, o.samples, dt); }));
    lanes_gain.push_back(t_scalar.back() / t_lanes.back());
    interleaved_gain.push_back(t_scalar.back() / t_interleaved.back());
  }
  size_t differ = 0;
  for (size_t r = 0; r < scalar.sums.size(); ++r)
    for (const Walked* other : {&lanes, &interleaved})
      if (std::fabs(scalar.sums[r] - other->sums[r]) > 1e-4f * (1.f + std::fabs(scalar.sums[r]))) ++differ;
  std::printf("tets %zu, rays %zu (of a %dx%d grid), samples up to %d, step %.4f (%.2f of the mean box width)\n",
              mesh.elements.size(), rays.start.size(), o.width, o.width, o.samples, double(dt), double(o.step));
  const auto report = [&](const char* name, const Walked& w, const std::vector<double>& t) {
    std::printf("%-12s %.3f s median of %d rounds, %llu record tests, %.2f ns a test\n", name, median(t), o.repeats,
                (unsigned long long)w.tests, 1e9 * median(t) / double(w.tests));
  };
  report("scalar:", scalar, t_scalar);
  report("lanes:", lanes, t_lanes);
  report("interleaved:", interleaved, t_interleaved);
  std::printf(
      "scalar / lanes %.2f [%.2f..%.2f], scalar / interleaved %.2f [%.2f..%.2f] (per round: median [min..max]);"
      " sums differing by more than 1e-4: %zu\n",
      median(lanes_gain), *std::min_element(lanes_gain.begin(), lanes_gain.end()),
      *std::max_element(lanes_gain.begin(), lanes_gain.end()), median(interleaved_gain),
      *std::min_element(interleaved_gain.begin(), interleaved_gain.end()),
      *std::max_element(interleaved_gain.begin(), interleaved_gain.end()), differ);
  return differ == 0 ? 0 : 1;
} catch (const std::exception& e) {
  std::fprintf(stderr, "volstream_bench_tet_walk: %s\n", e.what());
  return 2;
}
