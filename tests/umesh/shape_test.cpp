// VTK's shape functions and their inversion: a linear field is reproduced exactly by every
// element type, also in twisted hexes and wedges with non-planar faces; the weights are VTK's
// at known parametric points; points outside are refused.
#include "volstream/umesh/shape.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace vs {
namespace {

float linear(const vec3f& p) { return 0.5f + p.x + 2.f * p.y - 3.f * p.z; }

// Reference corners of each type (VTK order, positive orientation), distorted.
std::vector<vec3f> element(int n, std::mt19937& rng, float distortion) {
  std::vector<vec3f> x;
  if (n == 4) x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  if (n == 5) x = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 1}};
  if (n == 6) x = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}};
  if (n == 8) x = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  std::uniform_real_distribution<float> u(-distortion, distortion);
  for (vec3f& p : x) p = p + vec3f(u(rng), u(rng), u(rng));
  if (n == 8) {  // twist the top face by 20 degrees: its sides become non-planar
    const float c = std::cos(0.35f), s = std::sin(0.35f);
    for (int i = 4; i < 8; ++i) {
      const vec3f d = x[i] - vec3f(0.5f, 0.5f, 0.f);
      x[i] = vec3f(0.5f + c * d.x - s * d.y, 0.5f + s * d.x + c * d.y, x[i].z);
    }
  }
  return x;
}

vec3f random_params(int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.02f, 0.98f);
  vec3f pc(u(rng), u(rng), u(rng));
  if (n == 4 || n == 6) {  // inside the triangle (and the tet)
    while (pc.x + pc.y + (n == 4 ? pc.z : 0.f) > 0.98f) pc = vec3f(u(rng), u(rng), n == 4 ? u(rng) : pc.z);
  }
  return pc;
}

// The point of the element with corners x at parametric pc (VTK's map, also beyond its domain).
vec3f point_at(int n, const std::vector<vec3f>& x, const vec3f& pc) {
  float w[8];
  vec3f d[8];
  shape::weights(n, pc.x, pc.y, pc.z, w, d);
  vec3f p(0.f);
  for (int i = 0; i < n; ++i) p = p + x[size_t(i)] * w[i];
  return p;
}

class ShapeTest : public ::testing::TestWithParam<int> {};

TEST_P(ShapeTest, LinearFieldIsReproducedAtRandomInteriorPoints) {
  const int n = GetParam();
  std::mt19937 rng(n);
  for (int trial = 0; trial < 200; ++trial) {
    const std::vector<vec3f> x = element(n, rng, 0.12f);
    const vec3f p = point_at(n, x, random_params(n, rng));
    float found[8];
    ASSERT_TRUE(shape::locate_in_element(n, x.data(), p, found)) << "trial " << trial;
    float f = 0.f;
    for (int i = 0; i < n; ++i) f += found[i] * linear(x[size_t(i)]);
    EXPECT_NEAR(f, linear(p), 2e-5f) << "type " << n << " trial " << trial;
  }
}

// Newton's answer is the root to float noise, also where it stops after two steps on the
// convergence estimate (newton_converged): the weights at the parameters a point was made from.
TEST_P(ShapeTest, NewtonFindsTheRootToFloatNoise) {
  const int n = GetParam();
  std::mt19937 rng(100 + n);
  float worst = 0.f;
  for (int trial = 0; trial < 2000; ++trial) {
    const std::vector<vec3f> x = element(n, rng, 0.12f);
    const vec3f pc = random_params(n, rng);
    float exact[8], found[8];
    vec3f d[8];
    shape::weights(n, pc.x, pc.y, pc.z, exact, d);
    ASSERT_TRUE(shape::locate_in_element(n, x.data(), point_at(n, x, pc), found)) << "trial " << trial;
    for (int i = 0; i < n; ++i) worst = std::max(worst, std::fabs(found[i] - exact[i]));
  }
  EXPECT_LT(worst, 2e-6f) << "type " << n;
}

TEST_P(ShapeTest, PointsOutsideAreRefused) {
  const int n = GetParam();
  std::mt19937 rng(100 + n);
  const std::vector<vec3f> x = element(n, rng, 0.f);
  float w[8];
  for (const vec3f& p :
       {vec3f(-0.1f, 0.5f, 0.5f), vec3f(0.5f, 0.5f, 1.2f), vec3f(0.5f, -0.05f, 0.3f), vec3f(2.f, 2.f, 2.f)})
    EXPECT_FALSE(shape::locate_in_element(n, x.data(), p, w)) << p.x << " " << p.y << " " << p.z;
}

TEST_P(ShapeTest, WeightsPartitionUnityAndHitTheirCorner) {
  const int n = GetParam();
  std::mt19937 rng(7);
  const std::vector<vec3f> x = element(n, rng, 0.f);
  for (int c = 0; c < n; ++c) {
    if (n == 5 && c == 4) continue;  // the apex is the map's singular point
    float w[8];
    ASSERT_TRUE(shape::locate_in_element(n, x.data(), x[size_t(c)], w)) << c;
    float sum = 0.f;
    for (int i = 0; i < n; ++i) sum += w[i];
    EXPECT_NEAR(sum, 1.f, 1e-5f);
    EXPECT_NEAR(w[c], 1.f, 1e-4f) << "corner " << c;
  }
}

// The polynomial form Newton iterates on (shape::iso_map) is VTK's map: the same position as
// the weighted corners, and the same derivatives, at random parametric points of distorted and
// twisted elements.
TEST_P(ShapeTest, PolynomialFormEqualsTheWeightedCorners) {
  const int n = GetParam();
  if (n == 4) GTEST_SKIP() << "tets are located by one affine solve";
  std::mt19937 rng(300 + n);
  for (int trial = 0; trial < 100; ++trial) {
    const std::vector<vec3f> x = element(n, rng, 0.12f);
    const shape::IsoMap map = shape::iso_map(n, x.data());
    const vec3f pc = random_params(n, rng);
    float w[8];
    vec3f d[8];
    shape::weights(n, pc.x, pc.y, pc.z, w, d);
    vec3f pos(0.f), jr(0.f), js(0.f), jt(0.f);
    for (int i = 0; i < n; ++i) {
      pos = pos + x[size_t(i)] * w[i];
      jr = jr + x[size_t(i)] * d[i].x, js = js + x[size_t(i)] * d[i].y, jt = jt + x[size_t(i)] * d[i].z;
    }
    // One Newton step towards the point the weights give is zero: position and Jacobian agree.
    vec3f delta;
    ASSERT_TRUE(shape::newton_step(map, pos, pc, delta));
    EXPECT_LT(std::fabs(delta.x) + std::fabs(delta.y) + std::fabs(delta.z), 1e-5f) << "trial " << trial;
    // A step towards a point moved along one axis of the map is that axis' derivative solved.
    const vec3f moved = pos + jr * 1e-3f + js * 2e-3f - jt * 1e-3f;
    ASSERT_TRUE(shape::newton_step(map, moved, pc, delta));
    EXPECT_NEAR(delta.x, 1e-3f, 2e-5f) << "trial " << trial;
    EXPECT_NEAR(delta.y, 2e-3f, 2e-5f) << "trial " << trial;
    EXPECT_NEAR(delta.z, -1e-3f, 2e-5f) << "trial " << trial;
  }
}

#if defined(VS_SHAPE_LANES)
// The host's Newton step on lanes gives the step on vec3f: the same floats where nothing is
// contracted into FMA (the default build), else within a few float roundings.
TEST_P(ShapeTest, NewtonStepOnLanesEqualsTheStepOnVec3) {
  const int n = GetParam();
  if (n == 4) GTEST_SKIP() << "tets are located by one affine solve";
  std::mt19937 rng(700 + n);
  std::uniform_real_distribution<float> around(-0.5f, 1.5f);
  for (int trial = 0; trial < 1000; ++trial) {
    const std::vector<vec3f> x = element(n, rng, 0.2f);
    const shape::IsoMap map = shape::iso_map(n, x.data());
    shape::lanes::f4 lanes[8];
    for (int i = 0; i < 8; ++i) lanes[i] = simd::lanes_of(map.c[i]);
    const vec3f pc = random_params(n, rng), p(around(rng), around(rng), around(rng));
    vec3f scalar_delta, lanes_delta;
    const bool scalar_ok = shape::newton_step(map, p, pc, scalar_delta);
    ASSERT_EQ(shape::newton_step(lanes, simd::lanes_of(p), pc, lanes_delta), scalar_ok);
    if (!scalar_ok) continue;
    for (int a = 0; a < 3; ++a) {
#if defined(__FMA__)
      EXPECT_NEAR(lanes_delta[a], scalar_delta[a], 1e-5f * (1.f + std::fabs(scalar_delta[a]))) << "trial " << trial;
#else
      EXPECT_EQ(lanes_delta[a], scalar_delta[a]) << "trial " << trial;
#endif
    }
  }
}
#endif

// params_outside (selects, not branches) is the first largest face violation, as a plain scan of
// them says, at parametric points in, on and around every type's domain.
TEST_P(ShapeTest, ParamsOutsideIsTheFirstLargestViolation) {
  const int n = GetParam();
  std::mt19937 rng(800 + n);
  std::uniform_int_distribution<int> eighths(-4, 12);  // exact ties between faces happen
  for (int trial = 0; trial < 2000; ++trial) {
    const float r = eighths(rng) / 8.f, s = eighths(rng) / 8.f, t = eighths(rng) / 8.f;
    float v[shape::kMaxFaces];
    const int count = shape::face_violations(n, r, s, t, v);
    int expected_face = 0;
    for (int f = 1; f < count; ++f)
      if (v[f] > v[expected_face]) expected_face = f;
    float expected = v[expected_face];
    const bool above_apex = n == 5 && t > 1.f && expected < t - 1.f;
    if (above_apex) expected = t - 1.f;
    int face = -7;
    EXPECT_EQ(shape::params_outside(n, r, s, t, &face), expected) << r << " " << s << " " << t;
    EXPECT_EQ(face, above_apex ? -7 : expected_face) << r << " " << s << " " << t;
  }
}

// A walk's early exit (locate_in_element with early_out) never changes the answer: at random
// points in and around distorted and twisted elements it finds the same points inside, with the
// same weights and outside distance, as the iteration run to convergence, and a face for every
// point it refuses.
TEST_P(ShapeTest, EarlyOutGivesTheSameAnswerAsFullConvergence) {
  const int n = GetParam();
  std::mt19937 rng(500 + n);
  std::uniform_real_distribution<float> around(-0.3f, 1.3f);
  int inside = 0, refused = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const std::vector<vec3f> x = element(n, rng, 0.12f);
    // The map extended beyond the parameter domain: points inside and near every face.
    const vec3f p = point_at(n, x, vec3f{around(rng), around(rng), around(rng)});
    float w_full[8], w_early[8], out_full = -1.f, out_early = -1.f;
    int face_full = -1, face_early = -1;
    const bool full = shape::locate_in_element(n, x.data(), p, w_full, &out_full, &face_full, false);
    const bool early = shape::locate_in_element(n, x.data(), p, w_early, &out_early, &face_early, true);
    ASSERT_EQ(full, early) << "trial " << trial;
    if (full) {
      ++inside;
      EXPECT_EQ(out_full, out_early);
      for (int i = 0; i < n; ++i) EXPECT_EQ(w_full[i], w_early[i]) << "trial " << trial << " weight " << i;
    } else if (face_early >= 0) {
      ++refused;
      EXPECT_LT(face_early, shape::face_count(n));
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(refused, 1000);
}

// A tet's kept solve (the walk's hint, element_bvh.h) locates a second point with the same
// floats as a fresh locate_in_tet of the corners: weights, outside distance and face.
TEST(Shape, KeptTetSolveGivesTheFreshSolvesFloats) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> around(-0.5f, 1.5f);
  for (int trial = 0; trial < 2000; ++trial) {
    const std::vector<vec3f> x = element(4, rng, 0.3f);
    shape::TetSolve kept;
    float w0[4];
    shape::locate_in_tet(x.data(), x[0] * 0.25f + x[1] * 0.25f + x[2] * 0.25f + x[3] * 0.25f, w0, nullptr, nullptr,
                         &kept);
    const vec3f p = x[0] + (x[1] - x[0]) * around(rng) + (x[2] - x[0]) * around(rng) + (x[3] - x[0]) * around(rng);
    float w_fresh[4], w_kept[4], out_fresh = 0.f, out_kept = 1.f;
    int face_fresh = -1, face_kept = -2;
    const bool fresh = shape::locate_in_tet(x.data(), p, w_fresh, &out_fresh, &face_fresh);
    ASSERT_EQ(shape::tet_weights(kept, p, w_kept, &out_kept, &face_kept), fresh) << "trial " << trial;
    EXPECT_EQ(out_fresh, out_kept);
    EXPECT_EQ(face_fresh, face_kept);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(w_fresh[i], w_kept[i]) << "trial " << trial << " weight " << i;
  }
}

// A walk's kept solve (KeptSolve, the ray's hint) answers a second point nearby as a fresh
// locate_in_element does: the same points inside, the same weights to Newton's tolerance, a face
// for the points it refuses (a non-tet's iteration starts from the first point's parameters and
// may give up after one step).
TEST_P(ShapeTest, KeptSolveAnswersTheNextPointAsAFreshOne) {
  const int n = GetParam();
  std::mt19937 rng(900 + n);
  std::uniform_real_distribution<float> nudge(-0.4f, 0.4f);
  int inside = 0, refused = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const std::vector<vec3f> x = element(n, rng, 0.12f);
    const vec3f first_pc = random_params(n, rng);
    shape::KeptSolve kept;
    float w[8], outside;
    int face;
    ASSERT_TRUE(kept.locate(n, x.data(), point_at(n, x, first_pc), w, &outside, &face)) << "trial " << trial;
    kept.n = n;
    const vec3f p = point_at(n, x, first_pc + vec3f{nudge(rng), nudge(rng), nudge(rng)});
    float w_kept[8], w_fresh[8], out_kept = -1.f, out_fresh = -1.f;
    int face_kept = -1, face_fresh = -1, kept_n = 0;
    const bool fresh = shape::locate_in_element(n, x.data(), p, w_fresh, &out_fresh, &face_fresh, false);
    const bool again = kept.locate_again(p, w_kept, &out_kept, &face_kept, kept_n);
    EXPECT_EQ(kept_n, n);
    EXPECT_EQ(kept.n, 0);  // dropped until a walk keeps it again
    ASSERT_EQ(again, fresh) << "trial " << trial;
    if (fresh) {
      ++inside;
      EXPECT_NEAR(out_kept, out_fresh, 1e-5f);
      for (int i = 0; i < n; ++i) EXPECT_NEAR(w_kept[i], w_fresh[i], 1e-5f) << "trial " << trial << " weight " << i;
    } else {
      refused += face_kept >= 0 ? 1 : 0;
    }
  }
  EXPECT_GT(inside, 500);
  EXPECT_GT(refused, 500);
}

INSTANTIATE_TEST_SUITE_P(AllTypes, ShapeTest, ::testing::Values(4, 5, 6, 8),
                         [](const auto& p) { return std::to_string(p.param) + "_vertices"; });

// VTK's hexahedron at its parametric centre weighs all corners 1/8; its pyramid at (0.5, 0.5,
// 0.5) gives the apex 1/2 and each base corner 1/8; the wedge at (1/3, 1/3, 1/2) 1/6 each.
// The walk leaves a tet across the face opposite its most negative weight: the first of the
// smallest weights, as a scan finds it, also where weights tie.
TEST(Shape, TetWeightsOfNamesTheFirstSmallestWeight) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pick(-3, 3);  // few values: many ties
  for (int trial = 0; trial < 20000; ++trial) {
    const vec3f pc(0.25f * float(pick(rng)), 0.25f * float(pick(rng)), 0.25f * float(pick(rng)));
    float w[4];
    const int worst = shape::tet_weights_of(pc, w);
    EXPECT_EQ(w[0], 1.f - pc.x - pc.y - pc.z);
    EXPECT_EQ(worst, int(std::min_element(w, w + 4) - w)) << pc.x << " " << pc.y << " " << pc.z;
  }
}

TEST(Shape, WeightsAtKnownParametricPointsMatchVtk) {
  float w[8];
  vec3f d[8];
  shape::weights(8, 0.5f, 0.5f, 0.5f, w, d);
  for (int i = 0; i < 8; ++i) EXPECT_FLOAT_EQ(w[i], 0.125f);
  shape::weights(5, 0.5f, 0.5f, 0.5f, w, d);
  for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(w[i], 0.125f);
  EXPECT_FLOAT_EQ(w[4], 0.5f);
  shape::weights(6, 1.f / 3.f, 1.f / 3.f, 0.5f, w, d);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(w[i], 1.f / 6.f, 1e-6f);
}

}  // namespace
}  // namespace vs
