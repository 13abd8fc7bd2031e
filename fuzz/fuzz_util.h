// Shared by the fuzz targets: a scratch directory per process, and "patch a valid file" inputs
// (byte 0 picks the file, bytes 1-4 an offset; the rest overwrites the file there, or with the
// top bit of byte 0 set the file is truncated at the offset) so the fuzzer explores deep paths
// of the parsers starting from valid data.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "volstream/io/dataset.h"

namespace vs::fuzz {

std::filesystem::path scratch(const char* name);  // created once per process
// Copies one file's bytes (EINTR-safe, unlike std::filesystem::copy_file).
void copy_file_contents(const std::filesystem::path& from, const std::filesystem::path& to);
void copy_tree(const std::filesystem::path& from, const std::filesystem::path& to);  // replaces `to`
// Applies the patch in data to one of `files`; returns false if data is too short.
bool apply_patch(const std::vector<std::filesystem::path>& files, const uint8_t* data, size_t size);
// The same, telling which of `files` was patched (its index).
bool apply_patch(const std::vector<std::filesystem::path>& files, const uint8_t* data, size_t size, size_t& patched);
// Runs f; InputError and UsageError are the expected outcomes of bad input, anything else aborts.
void expect_clean(const std::function<void()>& f);
// Opens the mesh dataset in `dir` (either encoding) and, under expect_clean, probes it (through
// its point location and by brute force) and renders a tiny frame: opened whole, then opened
// deferred and restricted to a data-parallel rank's share (a compact mesh read part by part).
void exercise_mesh_dataset(const std::filesystem::path& dir);
void exercise_mesh_dataset(const std::filesystem::path& dir, TopologyLoad load);

}  // namespace vs::fuzz
