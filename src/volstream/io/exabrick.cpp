#include "volstream/io/exabrick.h"

#include <bit>

#include "volstream/core/error.h"
#include "volstream/io/binary_file.h"

namespace vs {
namespace {
static_assert(std::endian::native == std::endian::little,
              "ExaBrick files are little-endian; big-endian hosts need byte swaps");

class ExaBrickSource : public AmrSource {
 public:
  explicit ExaBrickSource(const ExaBrickInput& in) : in_(in) {
    const uint64_t size = file_size_checked(in.cells);
    if (size == 0 || size % sizeof(Cell) != 0)
      input_error(in.cells.string(),
                  "size " + std::to_string(size) + " is not a positive multiple of 16 bytes (4 x int32 per cell)");
    count_ = size / sizeof(Cell);
    if (in.scalars.empty()) input_error(in.cells.string(), "no scalar files given");
    for (const auto& s : in.scalars) {
      const uint64_t bytes = file_size_checked(s);
      if (bytes != count_ * sizeof(float))
        input_error(s.string(), "holds " + std::to_string(bytes) + " bytes, expected " + std::to_string(count_ * 4) +
                                    " (one float32 for each of the " + std::to_string(count_) + " cells)");
    }
  }
  std::vector<Cell> take_cells() override { return read_records<Cell>(in_.cells, count_); }
  uint64_t cell_count() const override { return count_; }
  WorldTransform transform() const override { return {}; }
  std::vector<std::string> field_names() const override {
    if (in_.as_time_series) return {in_.series_field_name};
    std::vector<std::string> names;
    for (const auto& s : in_.scalars) names.push_back(s.stem().string());
    return names;
  }
  int step_count() const override { return in_.as_time_series ? int(in_.scalars.size()) : 1; }
  void read_values(int field, int step, float* out) override {
    const auto& path = in_.scalars.at(size_t(in_.as_time_series ? step : field));
    read_exact(path, 0, out, count_ * sizeof(float));
  }
  std::string description() const override { return "ExaBrick cells " + in_.cells.filename().string(); }
  std::string origin() const override { return in_.cells.string(); }

 private:
  ExaBrickInput in_;
  uint64_t count_ = 0;
};
}  // namespace

std::unique_ptr<AmrSource> open_exabrick(const ExaBrickInput& input) { return std::make_unique<ExaBrickSource>(input); }

void write_exabrick_cells(const std::filesystem::path& path, const std::vector<Cell>& cells) {
  write_file(path, cells.data(), cells.size() * sizeof(Cell));
}
void write_exabrick_scalars(const std::filesystem::path& path, const std::vector<float>& values) {
  write_file(path, values.data(), values.size() * sizeof(float));
}

}  // namespace vs
