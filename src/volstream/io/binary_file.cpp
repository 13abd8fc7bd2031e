#include "volstream/io/binary_file.h"

#include <cctype>
#include <charconv>
#include <cstdio>
#include <memory>

#if defined(__linux__)
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>
#include <zlib.h>
#endif

#include "volstream/core/error.h"
#include "volstream/io/atomic_file.h"

namespace vs {
namespace {
struct FileCloser {
  void operator()(FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<FILE, FileCloser>;

FilePtr open_or_throw(const std::filesystem::path& path, const char* mode) {
  FILE* f = std::fopen(path.c_str(), mode);
  if (!f) input_error(path.string(), std::string("cannot open") + (mode[0] == 'w' ? " for writing" : ""));
  return FilePtr(f);
}
}  // namespace

uint64_t file_size_checked(const std::filesystem::path& path, uint64_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows links: a link to a regular file is fine
  if (st.type() == fs::file_type::not_found) input_error(path.string(), "does not exist");
  if (st.type() == fs::file_type::directory) input_error(path.string(), "is a directory, expected a file");
  // A FIFO, socket or device would block or never end: refuse before opening it.
  if (st.type() != fs::file_type::regular) input_error(path.string(), "is not a regular file");
  const auto size = fs::file_size(path, ec);
  if (ec) input_error(path.string(), "cannot read its size");
  if (uint64_t(size) > max_bytes)
    input_error(path.string(),
                "too large (" + std::to_string(size) + " bytes, at most " + std::to_string(max_bytes) + ")");
  return uint64_t(size);
}

void throw_size_mismatch(const std::filesystem::path& path, uint64_t size, uint64_t expected) {
  input_error(path.string(), "size " + std::to_string(size) + " bytes, expected " + std::to_string(expected));
}

void read_exact(const std::filesystem::path& path, uint64_t offset, void* dst, uint64_t bytes) {
  read_runs(path, {{offset, bytes}}, dst);
}

void read_runs(const std::filesystem::path& path, const std::vector<ByteRun>& runs, void* dst) {
  FilePtr f = open_or_throw(path, "rb");
  auto* out = static_cast<unsigned char*>(dst);
  for (const ByteRun& run : runs) {
    if (run.bytes == 0) continue;  // nothing to read (dst may be an empty vector's null data())
    if (fseeko(f.get(), off_t(run.offset), SEEK_SET) != 0)
      input_error(path.string(), "cannot seek to " + std::to_string(run.offset));
    if (std::fread(out, 1, run.bytes, f.get()) != run.bytes)
      input_error(path.string(), "truncated: expected " + std::to_string(run.bytes) + " bytes at offset " +
                                     std::to_string(run.offset));
    out += run.bytes;
  }
}

std::shared_ptr<const void> map_file(const std::filesystem::path& path, uint64_t bytes) {
#if defined(__linux__)
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) input_error(path.string(), "cannot open");
  // MAP_POPULATE maps every page now, in one call, rather than one page fault at a time later.
  void* p = ::mmap(nullptr, bytes, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
  ::close(fd);  // the mapping keeps the file
  if (p == MAP_FAILED) return nullptr;
  return std::shared_ptr<const void>(p, [bytes](const void* q) { ::munmap(const_cast<void*>(q), bytes); });
#else
  (void)path, (void)bytes;
  return nullptr;
#endif
}

std::string read_text_file(const std::filesystem::path& path, uint64_t max_bytes) {
  const uint64_t size = file_size_checked(path, max_bytes);
  std::string text(size, '\0');
  read_exact(path, 0, text.data(), size);
  return text;
}

namespace {

uint64_t half_the_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) / 2 : uint64_t(4) << 30;
}

// Deflate inflates at most 1032:1, so a gzip stream (one member or several) that inflates to
// more than that times its file is damaged.
constexpr uint64_t kMaxInflation = 1032;

std::string read_gzip_stream(const std::filesystem::path& path, uint64_t max_bytes, uint64_t inflate_cap) {
  const uint64_t ratio_cap = file_size_checked(path) * kMaxInflation + (1 << 16);
  const std::unique_ptr<gzFile_s, int (*)(gzFile)> gz(gzopen(path.string().c_str(), "rb"), gzclose);
  if (!gz) input_error(path.string(), "cannot open the gzip stream");
  std::string bytes;
  char buffer[1 << 16];
  int got = 0;
  while (bytes.size() < max_bytes && (got = gzread(gz.get(), buffer, sizeof buffer)) > 0) {
    bytes.append(buffer, size_t(got));
    if (bytes.size() > ratio_cap)
      input_error(path.string(), "the gzip stream inflates to more than " + std::to_string(kMaxInflation) +
                                     " times its size: a damaged stream");
    if (bytes.size() > inflate_cap)
      input_error(path.string(), "the gzip stream inflates past " + std::to_string(inflate_cap >> 20) +
                                     " MiB, more than this reader holds at once; gunzip it first if it is meant");
  }
  int status = Z_OK;
  const std::string message = gzerror(gz.get(), &status);
  if (got < 0 || !(status == Z_OK || status == Z_STREAM_END))
    input_error(path.string(), "a damaged gzip stream (" + message + ")");
  if (bytes.size() > max_bytes) bytes.resize(max_bytes);
  return bytes;
}

}  // namespace

std::string read_file_inflating(const std::filesystem::path& path, uint64_t max_bytes, uint64_t inflate_cap) {
  if (name_ends_with(path, ".gz"))
    return read_gzip_stream(path, max_bytes, inflate_cap ? inflate_cap : half_the_memory());
  const uint64_t size = std::min(file_size_checked(path), max_bytes);
  std::string bytes(size, '\0');
  read_exact(path, 0, bytes.data(), size);
  return bytes;
}

bool name_ends_with(const std::filesystem::path& file, std::string_view suffix) {
  return lower_case(file.filename().string()).ends_with(suffix);
}

std::string joined(const std::vector<std::string>& names, const char* separator) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : separator) + n;
  return s;
}

std::string lower_case(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool version_below(std::string_view version, int major, int minor) {
  int file_major = 0, file_minor = 0;
  const char* end = version.data() + version.size();
  const auto [dot, ec] = std::from_chars(version.data(), end, file_major);
  if (ec != std::errc()) return true;
  if (dot < end && *dot == '.') std::from_chars(dot + 1, end, file_minor);
  return file_major < major || (file_major == major && file_minor < minor);
}

std::string lower_extension(const std::filesystem::path& file) { return lower_case(file.extension().string()); }

void write_file(const std::filesystem::path& path, const void* data, uint64_t bytes, uint64_t pad_to) {
  write_file_atomic(path, data, bytes, pad_to);
}

}  // namespace vs
