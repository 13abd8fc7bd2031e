// Chunks: runs of a fixed number of consecutive items of an array stored in an order that keeps
// neighbours together (a mesh's element BVH items, a dataset's ABRs). A data-parallel rank
// chooses whole chunks by their stored boxes and reads each as one run of the files, so the
// index it reads whole is small (umesh/mesh_index.h, amr/abrs.h).
#pragma once
#include <algorithm>
#include <cstdint>

namespace vs {

inline constexpr uint32_t kIndexChunk = 32;

// Chunk c of an array of `count` items: positions [chunk_first, chunk_first + chunk_size).
inline uint64_t chunk_first(uint32_t c) { return uint64_t(c) * kIndexChunk; }
inline uint32_t chunk_size(uint32_t c, uint64_t count) {
  return uint32_t(std::min<uint64_t>(kIndexChunk, count - chunk_first(c)));
}
inline uint64_t chunk_count(uint64_t count) { return (count + kIndexChunk - 1) / kIndexChunk; }

}  // namespace vs
