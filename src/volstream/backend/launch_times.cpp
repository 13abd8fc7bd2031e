#include "volstream/backend/launch_times.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>

namespace vs {
namespace {
struct State {
  std::mutex mutex;
  std::map<std::string, LaunchTime> times;
};
State& state() {
  static State s;
  return s;
}
}  // namespace

void LaunchTimes::add(const char* name, double seconds) {
  State& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  LaunchTime& t = s.times[name];
  t.name = name;
  ++t.launches;
  t.seconds += seconds;
}

std::vector<LaunchTime> LaunchTimes::snapshot() const {
  State& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  std::vector<LaunchTime> out;
  for (const auto& [name, t] : s.times) out.push_back(t);
  return out;
}

void LaunchTimes::clear() {
  State& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  s.times.clear();
}

LaunchTimes& launch_times() {
  static LaunchTimes times;
  return times;
}

std::string format_launch_times(const std::vector<LaunchTime>& times) {
  std::vector<LaunchTime> sorted = times;
  std::sort(sorted.begin(), sorted.end(),
            [](const LaunchTime& a, const LaunchTime& b) { return a.seconds > b.seconds; });
  std::string out;
  for (const LaunchTime& t : sorted) {
    char part[160];
    std::snprintf(part, sizeof(part), "%s%s %llu x %.1f ms", out.empty() ? "" : ", ", t.name.c_str(),
                  (unsigned long long)t.launches, 1e3 * t.seconds / double(std::max<uint64_t>(t.launches, 1)));
    out += part;
  }
  return out;
}

}  // namespace vs
