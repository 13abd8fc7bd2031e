// A progress bar on stderr for long operations; silent when stderr is not a terminal (logs stay
// clean) unless forced.
#pragma once
#include <chrono>
#include <cstdint>
#include <string>

namespace vs {

class Progress {
 public:
  Progress(std::string label, uint64_t total, bool enabled = true);
  ~Progress();
  void advance(uint64_t by = 1);
  void set(uint64_t done);
  void set_detail(std::string detail) { detail_ = std::move(detail); }
  void finish();

 private:
  void draw(bool final);
  std::string label_, detail_;
  uint64_t total_, done_ = 0;
  bool enabled_, finished_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace vs
