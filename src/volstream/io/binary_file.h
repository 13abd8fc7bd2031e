// Checked binary file access: every read states how many bytes it expects, so a short or
// oversized file becomes an InputError instead of garbage.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "volstream/core/host_array.h"

namespace vs {

// The size of a regular file (links followed); InputError for a missing file, a directory, a
// FIFO, socket or device (which would block or never end), or a file over max_bytes. Every
// reader checks its input with this before opening it.
uint64_t file_size_checked(const std::filesystem::path& path, uint64_t max_bytes = UINT64_MAX);
// Reads exactly `bytes` bytes from `offset`; InputError if the file is shorter. Zero bytes read
// nothing (dst may be an empty vector's null data()).
void read_exact(const std::filesystem::path& path, uint64_t offset, void* dst, uint64_t bytes);
// Reads several byte ranges of one file back to back into dst, through one open file.
struct ByteRun {
  uint64_t offset, bytes;
};
void read_runs(const std::filesystem::path& path, const std::vector<ByteRun>& runs, void* dst);
// A whole text file (manifest, colour map, points, trace, plotfile header), at most max_bytes.
std::string read_text_file(const std::filesystem::path& path, uint64_t max_bytes = 64u << 20);
// A whole file (its first max_bytes), inflated through zlib where its name ends in ".gz" (any
// case; a gzip stream). InputError for a damaged stream (one inflating to more than deflate's
// 1032 times its size), and for one that inflates past `inflate_cap` bytes (by default half of
// this machine's memory: a small file can inflate a thousandfold, and would otherwise fill the
// memory before anything notices).
std::string read_file_inflating(const std::filesystem::path& path, uint64_t max_bytes = UINT64_MAX,
                                uint64_t inflate_cap = 0);
// Whether the file's name ends with `suffix` (lower case) in any case (".cas.gz" for "RUN.CAS.GZ").
bool name_ends_with(const std::filesystem::path& file, std::string_view suffix);
// ASCII letters in lower case, as the text readers compare keywords.
std::string lower_case(std::string_view s);
// The names one after another with `separator` between them ("fluid, solid"), for messages.
std::string joined(const std::vector<std::string>& names, const char* separator = ", ");
// Whether a file format's "MAJOR.MINOR" version (the leading part of `version`; "5.1", "2.2") is
// below major.minor; an unreadable one is (the oldest files have none), and a missing minor is 0.
bool version_below(std::string_view version, int major, int minor);
// The file name's extension in lower case (".vtu" for "Wing.VTU"), as the readers dispatch on it.
std::string lower_extension(const std::filesystem::path& file);
// Writes `bytes` bytes, zero-padded to a multiple of `pad_to` (1 = no padding), atomically
// (io/atomic_file.h: a temporary renamed into place, every write and the close checked).
void write_file(const std::filesystem::path& path, const void* data, uint64_t bytes, uint64_t pad_to = 1);

[[noreturn]] void throw_size_mismatch(const std::filesystem::path& path, uint64_t size, uint64_t expected);

// The bytes of `count` records of T, after checking that the file holds them and less than
// `allowed_padding` bytes more.
template <typename T>
uint64_t checked_record_bytes(const std::filesystem::path& path, uint64_t count, uint64_t allowed_padding) {
  const uint64_t size = file_size_checked(path);
  const uint64_t bytes = count * sizeof(T);
  if (count > (uint64_t(1) << 40) / sizeof(T) || size < bytes || size - bytes >= allowed_padding)
    throw_size_mismatch(path, size, bytes);
  return bytes;
}

// Reads a whole file of trivially copyable records; the size must be exactly count * sizeof(T).
template <typename T>
std::vector<T> read_records(const std::filesystem::path& path, uint64_t count, uint64_t allowed_padding = 1) {
  const uint64_t bytes = checked_record_bytes<T>(path, count, allowed_padding);
  std::vector<T> out(count);
  read_exact(path, 0, out.data(), bytes);
  return out;
}

// The first `bytes` bytes of a file mapped read-only into memory, kept mapped while the returned
// owner lives; null where the system cannot map it (then read it instead).
std::shared_ptr<const void> map_file(const std::filesystem::path& path, uint64_t bytes);

// read_records' array as a view of the mapped file (core/host_array.h: no fresh memory to
// fault in and no copy), or read as read_records does where the file cannot be mapped.
template <typename T>
HostArray<T> map_records(const std::filesystem::path& path, uint64_t count, uint64_t allowed_padding = 1) {
  const uint64_t bytes = checked_record_bytes<T>(path, count, allowed_padding);
  if (bytes == 0) return {};
  std::shared_ptr<const void> mapping = map_file(path, bytes);
  if (!mapping) return read_records<T>(path, count, allowed_padding);
  return HostArray<T>::view(mapping, static_cast<const T*>(mapping.get()), count);
}

}  // namespace vs
