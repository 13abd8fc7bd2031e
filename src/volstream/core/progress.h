// A progress bar on stderr for long operations; silent when stderr is not a terminal (logs stay
// clean) unless forced with the environment variable VOLSTREAM_PROGRESS=always (tests).
//
// finish() completes the bar (100%). A run that stops early must not look complete: fail() (or
// the destructor, when the bar is destroyed by an exception, or without finish()) ends the line
// where it stopped, e.g. "playing      [######........] failed at frame 3/8  1.2s".
#pragma once
#include <chrono>
#include <cstdint>
#include <string>
#include "volstream/core/stopwatch.h"

namespace vs {

class Progress {
 public:
  // `unit` names one item in the end-of-line messages ("frame": "failed at frame 3/8").
  Progress(std::string label, uint64_t total, bool enabled = true, std::string unit = "");
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  void advance(uint64_t by = 1);
  void set(uint64_t done);
  void set_detail(std::string detail) { detail_ = std::move(detail); }
  void finish();  // success: the bar at 100%, then a new line
  void fail();    // the run stopped at item done + 1: "failed at <unit> N/total", then a new line

  // The end-of-line text of a stopped run, e.g. "failed at frame 3/8" (for tests and logs).
  static std::string stopped_text(const char* verb, const std::string& unit, uint64_t done, uint64_t total);

 private:
  void draw(bool final);
  void draw_stopped(const char* verb);
  std::string label_, detail_, unit_;
  uint64_t total_, done_ = 0;
  bool enabled_, finished_ = false;
  int uncaught_ = 0;  // std::uncaught_exceptions() at construction
  Stopwatch started_, since_draw_;
};

}  // namespace vs
