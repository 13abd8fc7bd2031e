#include "volstream/io/binary_file.h"

#include <cstdio>
#include <memory>

#include "volstream/core/error.h"

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

uint64_t file_size_checked(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) input_error(path.string(), "missing (or not a regular file)");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) input_error(path.string(), "cannot read its size");
  return uint64_t(size);
}

void throw_size_mismatch(const std::filesystem::path& path, uint64_t size, uint64_t expected) {
  input_error(path.string(), "size " + std::to_string(size) + " bytes, expected " + std::to_string(expected));
}

void read_exact(const std::filesystem::path& path, uint64_t offset, void* dst, uint64_t bytes) {
  FilePtr f = open_or_throw(path, "rb");
  if (fseeko(f.get(), off_t(offset), SEEK_SET) != 0) input_error(path.string(), "cannot seek to " + std::to_string(offset));
  if (std::fread(dst, 1, bytes, f.get()) != bytes)
    input_error(path.string(), "truncated: expected " + std::to_string(bytes) + " bytes at offset " + std::to_string(offset));
}

std::string read_text_file(const std::filesystem::path& path, uint64_t max_bytes) {
  const uint64_t size = file_size_checked(path);
  if (size > max_bytes) input_error(path.string(), "too large for a text file (" + std::to_string(size) + " bytes)");
  std::string text(size, '\0');
  if (size) read_exact(path, 0, text.data(), size);
  return text;
}

void write_file(const std::filesystem::path& path, const void* data, uint64_t bytes, uint64_t pad_to) {
  FilePtr f = open_or_throw(path, "wb");
  if (bytes && std::fwrite(data, 1, bytes, f.get()) != bytes) input_error(path.string(), "write failed (disk full?)");
  const uint64_t padded = (bytes + pad_to - 1) / pad_to * pad_to;
  static const char zeros[4096] = {};
  for (uint64_t left = padded - bytes; left > 0;) {
    const uint64_t chunk = left < sizeof(zeros) ? left : sizeof(zeros);
    if (std::fwrite(zeros, 1, chunk, f.get()) != chunk) input_error(path.string(), "write failed (disk full?)");
    left -= chunk;
  }
  if (std::fflush(f.get()) != 0) input_error(path.string(), "write failed (disk full?)");
}

}  // namespace vs
