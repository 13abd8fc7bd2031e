#include "volstream/stream/step_reader.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <utility>
#include <vector>

#include "volstream/core/error.h"
#include "volstream/cuda/pinned.h"

namespace vs::stream {
namespace {

uint64_t round_up(uint64_t n) { return (n + kIoAlignment - 1) / kIoAlignment * kIoAlignment; }

std::string errno_text(int e) { return std::strerror(e); }

// Closes the descriptor on every path out of a read.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------------
const char* pinning_name(HostBuffer::Pinning p) {
  switch (p) {
    case HostBuffer::Pinning::cuda:
      return "page-locked (cudaHostAlloc)";
    case HostBuffer::Pinning::mlock:
      return "page-locked (mlock)";
    default:
      return "pageable";
  }
}

HostBuffer::HostBuffer(uint64_t bytes, bool want_pinned, const char* structure)
    : bytes_(round_up(std::max<uint64_t>(bytes, 1))) {
  if (want_pinned) {
    // CUDA's page-locked memory is what makes host-to-device copies fast; without CUDA, mlock()
    // gives the same guarantee to the OS (no paging), which is all a CPU "upload" can use.
    std::string cuda_why;
    data_ = cuda::pinned_host_alloc(bytes_, cuda_why);
    if (data_) pinning_ = Pinning::cuda;
    if (!data_) {
      data_ = std::aligned_alloc(kIoAlignment, bytes_);
      if (!data_) throw std::bad_alloc();
      if (::mlock(data_, bytes_) == 0) {
        pinning_ = Pinning::mlock;
      } else {
        pin_failure_ = cuda_why + "; mlock: " + errno_text(errno) + " (RLIMIT_MEMLOCK, see ulimit -l)";
      }
    }
  } else {
    data_ = std::aligned_alloc(kIoAlignment, bytes_);
    if (!data_) throw std::bad_alloc();
  }
  std::memset(data_, 0, bytes_);
  counted_ =
      CountedBytes(structure, pinning_ == Pinning::none ? MemorySpace::host : MemorySpace::pinned, int64_t(bytes_));
}

HostBuffer& HostBuffer::operator=(HostBuffer&& o) noexcept {
  if (this != &o) {
    release();
    data_ = std::exchange(o.data_, nullptr);
    bytes_ = std::exchange(o.bytes_, 0);
    pinning_ = std::exchange(o.pinning_, Pinning::none);
    counted_ = std::move(o.counted_);
    pin_failure_ = std::move(o.pin_failure_);
  }
  return *this;
}

HostBuffer::~HostBuffer() { release(); }

void HostBuffer::release() {
  if (!data_) return;
  if (pinning_ == Pinning::cuda) {
    cuda::pinned_host_free(data_);
  } else {
    if (pinning_ == Pinning::mlock) ::munlock(data_, bytes_);
    std::free(data_);
  }
  data_ = nullptr;
}

// ---------------------------------------------------------------------------------------------
StepReader::StepReader(uint64_t value_count, ReadMode mode)
    : value_bytes_(value_count * sizeof(float)),
      padded_bytes_(round_up(value_count * sizeof(float))),
      direct_(mode == ReadMode::direct) {}

void StepReader::fall_back(const std::filesystem::path& file, int error) {
  static std::atomic<bool> warned{false};
  direct_ = false;
  if (!warned.exchange(true))
    std::fprintf(stderr, "volstream: warning: %s: the file system refuses O_DIRECT (%s); using buffered reads\n",
                 file.parent_path().c_str(), errno_text(error).c_str());
}

int StepReader::open_file(const std::filesystem::path& file, int step) {
  const std::string where = "step " + std::to_string(step) + ": ";
  // What the path is, before any O_DIRECT attempt: a directory would be refused O_DIRECT
  // (a bogus warning) and a FIFO would block the open until someone writes to it.
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) {
    if (errno == ENOENT) input_error(file.string(), where + "values file is missing");
    input_error(file.string(), where + "cannot open: " + errno_text(errno));
  }
  if (!S_ISREG(st.st_mode))
    input_error(file.string(), where + (S_ISDIR(st.st_mode) ? "is a directory" : "not a regular file"));
  for (;;) {
    const bool direct = direct_.load();
    // O_NONBLOCK: should the path become a FIFO after the check, the open still returns.
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | (direct ? O_DIRECT : 0));
    if (fd >= 0) return fd;
    const int e = errno;
    if (e == EINVAL && direct) {
      fall_back(file, e);
      continue;
    }
    if (e == ENOENT) input_error(file.string(), where + "values file is missing");
    input_error(file.string(), where + "cannot open: " + errno_text(e));
  }
}

// Reads the file into dst; false when O_DIRECT was refused mid-read (the caller retries buffered).
bool StepReader::read_all(int fd, const std::filesystem::path& file, int step, char* dst) {
  const std::string where = "step " + std::to_string(step) + ": ";
  const bool direct = direct_.load();
  // Direct reads must cover whole 4 KiB blocks (the padding); buffered ones need only the values.
  const uint64_t want = direct ? padded_bytes_ : value_bytes_;
  constexpr uint64_t kChunk = uint64_t(64) << 20;
  uint64_t done = 0;
  while (done < want) {
    const uint64_t request = std::min(kChunk, want - done);
    const ssize_t n = ::pread(fd, dst + done, size_t(request), off_t(done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EINVAL && direct) {
      fall_back(file, errno);
      return false;
    }
    if (n < 0) input_error(file.string(), where + "read failed: " + errno_text(errno));
    done += uint64_t(n);
    // End of file. A short direct read also ends here: the file is not padded, and O_DIRECT
    // cannot go on from an unaligned offset.
    if (n == 0 || (direct && uint64_t(n) < request)) break;
  }
  if (done < value_bytes_)
    input_error(file.string(), where + "truncated while reading: " + std::to_string(done) + " of " +
                                   std::to_string(value_bytes_) + " bytes");
  bytes_read_ += done;
  return true;
}

void StepReader::read(const std::filesystem::path& file, int step, void* dst) {
  const std::string where = "step " + std::to_string(step) + ": ";
  for (;;) {
    Fd fd{open_file(file, step)};
    struct stat st {};
    if (::fstat(fd.fd, &st) != 0 || !S_ISREG(st.st_mode)) input_error(file.string(), where + "not a regular file");
    // The file holds exactly the values, zero-padded to 4 KiB; anything else is a different
    // dataset or a damaged file, and reading it would render garbage.
    const uint64_t size = uint64_t(st.st_size);
    const std::string expected =
        "expected " + std::to_string(value_bytes_) + " bytes of values padded to " + std::to_string(padded_bytes_);
    if (size < value_bytes_)
      input_error(file.string(), where + "truncated: " + std::to_string(size) + " bytes, " + expected);
    if (size > padded_bytes_)
      input_error(file.string(), where + "wrong size: " + std::to_string(size) + " bytes, " + expected);
    if (!direct_.load()) ::posix_fadvise(fd.fd, 0, 0, POSIX_FADV_SEQUENTIAL);
    if (read_all(fd.fd, file, step, static_cast<char*>(dst))) return;
  }
}

// ---------------------------------------------------------------------------------------------
bool evict_from_page_cache(const std::filesystem::path& file) {
  Fd fd{::open(file.c_str(), O_RDONLY | O_CLOEXEC)};
  if (fd.fd < 0) return false;
  ::fdatasync(fd.fd);  // dirty pages cannot be dropped; write them back first
  return ::posix_fadvise(fd.fd, 0, 0, POSIX_FADV_DONTNEED) == 0;
}

double page_cache_resident_fraction(const std::filesystem::path& file) {
  Fd fd{::open(file.c_str(), O_RDONLY | O_CLOEXEC)};
  struct stat st {};
  if (fd.fd < 0 || ::fstat(fd.fd, &st) != 0) return -1;
  if (st.st_size == 0) return 0;
  void* map = ::mmap(nullptr, size_t(st.st_size), PROT_READ, MAP_SHARED, fd.fd, 0);
  if (map == MAP_FAILED) return -1;
  const long page = ::sysconf(_SC_PAGESIZE);
  const size_t pages = (size_t(st.st_size) + size_t(page) - 1) / size_t(page);
  std::vector<unsigned char> resident(pages);
  double fraction = -1;
  if (::mincore(map, size_t(st.st_size), resident.data()) == 0) {
    size_t n = 0;
    for (unsigned char r : resident) n += r & 1;
    fraction = double(n) / double(pages);
  }
  ::munmap(map, size_t(st.st_size));
  return fraction;
}

}  // namespace vs::stream
