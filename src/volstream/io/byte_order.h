// Fixed-size values in a chosen byte order, for the binary mesh formats (legacy VTK is big
// endian, UGRID comes in both orders). Loads and stores go through memcpy, so unaligned buffers
// are fine.
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

namespace vs {

template <typename T>
T load_value(const char* p, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));  // the hosts we build for are little endian
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

// `n` values of type T stored back to back at p, each converted to Out: a list's values read in
// one loop, its bounds checked once by the caller (the branch on the byte order out of the loop).
template <typename T, typename Out>
void load_values(const char* p, uint64_t n, bool big_endian, Out* out) {
  if (big_endian)
    for (uint64_t i = 0; i < n; ++i) out[i] = Out(load_value<T>(p + i * sizeof(T), true));
  else
    for (uint64_t i = 0; i < n; ++i) out[i] = Out(load_value<T>(p + i * sizeof(T), false));
}

template <typename T>
void append_value(std::string& out, T v, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

}  // namespace vs
