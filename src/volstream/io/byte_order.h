// Fixed-size values in a chosen byte order, for the binary mesh formats (legacy VTK is big
// endian, UGRID comes in both orders). Loads and stores go through memcpy, so unaligned buffers
// are fine.
#pragma once
#include <algorithm>
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

template <typename T>
void append_value(std::string& out, T v, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

}  // namespace vs
