// Small vector and box types shared by host and device code.
#pragma once
#include <cmath>
#include <cstdint>
#include <type_traits>

#if defined(__CUDACC__)
#define VS_HOST_DEVICE __host__ __device__
#else
#define VS_HOST_DEVICE
#endif

// For the per-sample functions that the compiler's size heuristics leave out of line inside the
// large integrator (measured: a quarter of the time in a call to the sampler).
#if defined(__CUDACC__)
#define VS_FORCE_INLINE __forceinline__
#elif defined(__GNUC__)
#define VS_FORCE_INLINE inline __attribute__((always_inline))
#else
#define VS_FORCE_INLINE inline
#endif

namespace vs {

template <typename T>
struct Vec3 {
  T x{}, y{}, z{};
  VS_HOST_DEVICE constexpr Vec3() = default;
  VS_HOST_DEVICE constexpr Vec3(T a, T b, T c) : x(a), y(b), z(c) {}
  VS_HOST_DEVICE constexpr explicit Vec3(T s) : x(s), y(s), z(s) {}
  template <typename U>
  VS_HOST_DEVICE constexpr explicit Vec3(const Vec3<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}
  VS_HOST_DEVICE constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  VS_HOST_DEVICE constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

using vec3f = Vec3<float>;
using vec3d = Vec3<double>;
using vec3i = Vec3<int32_t>;

#define VS_VEC_BINOP(op)                                                             \
  template <typename T>                                                              \
  VS_HOST_DEVICE constexpr Vec3<T> operator op(const Vec3<T>& a, const Vec3<T>& b) { \
    return {a.x op b.x, a.y op b.y, a.z op b.z};                                     \
  }                                                                                  \
  template <typename T>                                                              \
  VS_HOST_DEVICE constexpr Vec3<T> operator op(const Vec3<T>& a, T s) {              \
    return {a.x op s, a.y op s, a.z op s};                                           \
  }
VS_VEC_BINOP(+)
VS_VEC_BINOP(-)
VS_VEC_BINOP(*)
VS_VEC_BINOP(/)
#undef VS_VEC_BINOP

template <typename T>
VS_HOST_DEVICE constexpr Vec3<T> operator-(const Vec3<T>& a) {
  return {-a.x, -a.y, -a.z};
}
template <typename T>
VS_HOST_DEVICE constexpr Vec3<T> operator*(T s, const Vec3<T>& a) {
  return a * s;
}
template <typename T>
VS_HOST_DEVICE constexpr bool operator==(const Vec3<T>& a, const Vec3<T>& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}
template <typename T>
VS_HOST_DEVICE constexpr T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <typename T>
VS_HOST_DEVICE constexpr Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename T>
VS_HOST_DEVICE inline T length(const Vec3<T>& a) {
  return std::sqrt(dot(a, a));
}
template <typename T>
VS_HOST_DEVICE inline Vec3<T> normalize(const Vec3<T>& a) {
  return a / length(a);
}
template <typename T>
VS_HOST_DEVICE constexpr Vec3<T> vmin(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
template <typename T>
VS_HOST_DEVICE constexpr Vec3<T> vmax(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}
template <typename T>
VS_HOST_DEVICE constexpr T reduce_min(const Vec3<T>& a) {
  return a.x < a.y ? (a.x < a.z ? a.x : a.z) : (a.y < a.z ? a.y : a.z);
}
template <typename T>
VS_HOST_DEVICE constexpr T reduce_max(const Vec3<T>& a) {
  return a.x > a.y ? (a.x > a.z ? a.x : a.z) : (a.y > a.z ? a.y : a.z);
}

// Axis-aligned box [lower, upper]. An empty box has lower > upper.
template <typename T>
struct Box3 {
  Vec3<T> lower, upper;
  VS_HOST_DEVICE constexpr bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  VS_HOST_DEVICE constexpr Vec3<T> size() const { return upper - lower; }
  VS_HOST_DEVICE constexpr Vec3<T> center() const { return (lower + upper) / T(2); }
  VS_HOST_DEVICE constexpr void extend(const Vec3<T>& p) {
    lower = vmin(lower, p);
    upper = vmax(upper, p);
  }
  VS_HOST_DEVICE constexpr void extend(const Box3& b) {
    lower = vmin(lower, b.lower);
    upper = vmax(upper, b.upper);
  }
  VS_HOST_DEVICE constexpr bool contains(const Vec3<T>& p) const {
    return p.x >= lower.x && p.y >= lower.y && p.z >= lower.z && p.x <= upper.x && p.y <= upper.y && p.z <= upper.z;
  }
  // Every point of b (NaN corners: false).
  VS_HOST_DEVICE constexpr bool contains(const Box3& b) const { return contains(b.lower) && contains(b.upper); }
  // True when the open interiors of the two boxes intersect.
  VS_HOST_DEVICE constexpr bool overlaps_open(const Box3& b) const {
    return lower.x < b.upper.x && b.lower.x < upper.x && lower.y < b.upper.y && b.lower.y < upper.y &&
           lower.z < b.upper.z && b.lower.z < upper.z;
  }
  static constexpr Box3 make_empty();
};
using box3f = Box3<float>;
using box3i = Box3<int32_t>;

template <typename T>
constexpr Box3<T> Box3<T>::make_empty() {
  if constexpr (std::is_floating_point_v<T>) {
    return {Vec3<T>(T(INFINITY)), Vec3<T>(T(-INFINITY))};
  } else {
    return {Vec3<T>(T(INT32_MAX)), Vec3<T>(T(INT32_MIN))};
  }
}

}  // namespace vs
