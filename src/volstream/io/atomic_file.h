// Output files that appear whole or not at all: written under a temporary name in the target's
// directory (mkstemp: never follows a planted link), every write and the close checked, renamed
// over the target on commit(); a failure or a destructor before commit() removes the temporary.
#pragma once
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "volstream/io/cleanup.h"

namespace vs {

class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path target);  // InputError naming the target if it cannot be created
  ~AtomicFile();                                      // removes the temporary unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const void* data, uint64_t bytes);  // InputError on a short write (disk full)
  void write(const std::string& text) { write(text.data(), text.size()); }
  // Flushes, syncs and closes (each checked), then renames over the target.
  void commit();
  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temp_path() const { return temp_; }

 private:
  [[noreturn]] void fail(const std::string& what, int error);
  std::filesystem::path target_, temp_;
  FILE* file_ = nullptr;
  bool committed_ = false;
  std::unique_ptr<RemoveOnSignal> on_signal_;  // Ctrl-C leaves no temporary behind
};

// A directory built under a temporary name beside `target` and swapped in whole by commit(), so
// that a failure part way leaves `target` as it was (absent, or the old contents). `target` must
// be absent, an empty directory, or hold `marker` (a file of what it replaces, e.g. a dataset's
// manifest.json): any other directory, a file or a symbolic link is refused, never written into.
class StagedDirectory {
 public:
  StagedDirectory(std::filesystem::path target, const std::string& marker);
  ~StagedDirectory();  // removes the temporary tree unless committed
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;
  const std::filesystem::path& path() const { return temp_; }  // where to write
  void commit();  // atomically exchanges with an existing target, then removes the old tree

 private:
  std::filesystem::path target_, temp_;
  bool committed_ = false;
  std::unique_ptr<RemoveOnSignal> on_signal_;
};

// The whole file in one go: `bytes` bytes, zero-padded to a multiple of `pad_to`.
void write_file_atomic(const std::filesystem::path& path, const void* data, uint64_t bytes, uint64_t pad_to = 1);

// A temporary name beside `target` (same directory, so a rename is atomic), e.g. for ffmpeg's
// output: ".<name>.part-XXXXXX" made unique by mkstemp and created empty, mode 0644.
std::filesystem::path make_temp_beside(const std::filesystem::path& target);

// InputError unless `dir` (the parent of an output, "." when empty) is a directory we can write
// into: checked before a long render, not after.
void check_output_directory(const std::filesystem::path& output);

}  // namespace vs
