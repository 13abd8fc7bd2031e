// Raw uniform grids (x fastest, no header) as single-level AMR data.
#pragma once
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "volstream/amr/source.h"

namespace vs {

enum class RawType { u8, u16, i16, u32, i32, f32, f64 };
RawType parse_raw_type(const std::string& name);  // "uint8", "float32", ...; UsageError otherwise
size_t raw_type_size(RawType t);

struct RawGridInput {
  std::vector<std::filesystem::path> files;  // one per step (or per field with fields_from_files)
  vec3i dims{0, 0, 0};
  RawType type = RawType::f32;
  bool big_endian = false;
  bool files_are_fields = false;  // each file a field named by its stem instead of a step
  std::string field_name = "scalar";
  vec3d origin{0, 0, 0}, spacing{1, 1, 1};
};

std::unique_ptr<AmrSource> open_raw_grid(const RawGridInput& input);

}  // namespace vs
