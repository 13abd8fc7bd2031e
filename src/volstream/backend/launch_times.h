// Time spent in each named kernel launch (parallel_for), on the CPU (wall clock around the
// oneTBB loop) and on the GPU (CUDA events, collected after the stream's work is done).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace vs {

struct LaunchTime {
  std::string name;
  uint64_t launches = 0;
  double seconds = 0;
};

// Process-wide, thread-safe.
class LaunchTimes {
 public:
  void add(const char* name, double seconds);
  std::vector<LaunchTime> snapshot() const;  // sorted by name
  void clear();
};
LaunchTimes& launch_times();

// "render 3 x 120.4 ms, abr_ranges 3 x 8.1 ms, ...", most time first.
std::string format_launch_times(const std::vector<LaunchTime>& times);

}  // namespace vs
