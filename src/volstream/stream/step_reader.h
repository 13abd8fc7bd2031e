// Reading one (field, step) values file into a caller-provided host buffer, by buffered pread or
// by direct I/O (O_DIRECT, bypassing the page cache: paper 000, section 5.4), and the aligned,
// optionally page-locked host buffers it reads into.
#pragma once
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <string>
#include "volstream/backend/memory.h"

namespace vs::stream {

inline constexpr uint64_t kIoAlignment = 4096;  // O_DIRECT buffer, offset and size granularity

// Host memory aligned to 4 KiB, its size rounded up to 4 KiB, zero-filled (so every page is
// resident before the first frame), and page-locked when asked and possible.
class HostBuffer {
 public:
  enum class Pinning { none, cuda, mlock };

  HostBuffer() = default;
  // Counted in the memory ledger as `structure` (pinned or host memory).
  HostBuffer(uint64_t bytes, bool want_pinned, const char* structure = "staging");
  ~HostBuffer();
  HostBuffer(HostBuffer&& o) noexcept { *this = std::move(o); }
  HostBuffer& operator=(HostBuffer&& o) noexcept;
  HostBuffer(const HostBuffer&) = delete;
  HostBuffer& operator=(const HostBuffer&) = delete;

  void* data() const { return data_; }
  float* floats() const { return static_cast<float*>(data_); }
  uint64_t bytes() const { return bytes_; }
  Pinning pinning() const { return pinning_; }
  // Why page-locking was not possible (empty when it was, or was not asked for).
  const std::string& pin_failure() const { return pin_failure_; }

 private:
  void release();
  void* data_ = nullptr;
  uint64_t bytes_ = 0;
  Pinning pinning_ = Pinning::none;
  CountedBytes counted_;
  std::string pin_failure_;
};
const char* pinning_name(HostBuffer::Pinning p);

enum class ReadMode { buffered, direct };

// Reads whole values files of `value_count` float32 (padded to 4 KiB on disk). Errors are
// InputError(file, "step N: ..."): a missing file, one shorter than the values (truncated), one
// longer than values + padding (wrong size), or a failing read. When the file system refuses
// O_DIRECT (EINVAL, e.g. tmpfs) the reader falls back to buffered reads and warns once on stderr.
class StepReader {
 public:
  StepReader(uint64_t value_count, ReadMode mode);

  uint64_t value_bytes() const { return value_bytes_; }
  uint64_t padded_bytes() const { return padded_bytes_; }
  // `dst` must hold padded_bytes() and, for direct reads, be 4 KiB aligned (a HostBuffer is).
  void read(const std::filesystem::path& file, int step, void* dst);

  bool direct() const { return direct_.load(); }  // false in buffered mode or after a fallback
  uint64_t bytes_read() const { return bytes_read_.load(); }

 private:
  int open_file(const std::filesystem::path& file, int step);
  bool read_all(int fd, const std::filesystem::path& file, int step, char* dst);
  void fall_back(const std::filesystem::path& file, int error);

  uint64_t value_bytes_, padded_bytes_;
  std::atomic<bool> direct_;
  std::atomic<uint64_t> bytes_read_{0};
};

// Drops a file's clean pages from the page cache (fdatasync + posix_fadvise(POSIX_FADV_DONTNEED),
// which needs no privileges). Returns false if the file cannot be opened or advised.
bool evict_from_page_cache(const std::filesystem::path& file);
// Fraction of the file's pages in the page cache (mmap + mincore); -1 if it cannot be measured.
double page_cache_resident_fraction(const std::filesystem::path& file);

}  // namespace vs::stream
