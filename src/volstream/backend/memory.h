// Every allocation of the large structures, counted per structure and memory space, so that
// `info`, `render` and `play` can say where the bytes are (host, page-locked host, device).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace vs {

enum class MemorySpace { host = 0, pinned = 1, device = 2 };
const char* to_string(MemorySpace space);

struct MemoryEntry {
  std::string structure;
  int64_t bytes[3] = {0, 0, 0};  // current, per MemorySpace
  int64_t peak[3] = {0, 0, 0};
};

// Process-wide, thread-safe.
class MemoryLedger {
 public:
  void add(const std::string& structure, MemorySpace space, int64_t bytes);  // negative: freed
  std::vector<MemoryEntry> snapshot() const;                                 // sorted by structure
  int64_t total(MemorySpace space) const;
};
MemoryLedger& memory_ledger();

// "device 12.3 MiB (ABRs 4.1, BVH 2.0, ...)": one line per space in use.
std::string format_memory(const std::vector<MemoryEntry>& entries);
// The process's peak resident set (MiB): what a user compares with host memory for long series,
// and what a data-parallel rank's share of a dataset bounds.
double peak_rss_mib();

// Bytes of one structure counted for as long as this object lives (RAII; movable).
class CountedBytes {
 public:
  CountedBytes() = default;
  CountedBytes(std::string structure, MemorySpace space, int64_t bytes = 0);
  CountedBytes(CountedBytes&& o) noexcept;
  CountedBytes& operator=(CountedBytes&& o) noexcept;
  CountedBytes(const CountedBytes&) = delete;
  CountedBytes& operator=(const CountedBytes&) = delete;
  ~CountedBytes();
  void set(int64_t bytes);  // the structure's size now
  int64_t bytes() const { return bytes_; }

 private:
  std::string structure_;
  MemorySpace space_ = MemorySpace::host;
  int64_t bytes_ = 0;
};

}  // namespace vs
