#include "volstream/core/progress.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>

namespace vs {

namespace {
bool forced() {
  const char* v = std::getenv("VOLSTREAM_PROGRESS");
  return v && std::strcmp(v, "always") == 0;
}

std::string bar_of(uint64_t done, uint64_t total) {
  constexpr int kWidth = 30;
  const double fraction = total ? double(done) / double(total) : 1.0;
  std::string bar(size_t(int(fraction * kWidth + 0.5)), '#');
  bar.resize(kWidth, '.');
  return bar;
}
}  // namespace

Progress::Progress(std::string label, uint64_t total, bool enabled, std::string unit)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(enabled && (isatty(STDERR_FILENO) || forced())),
      uncaught_(std::uncaught_exceptions()) {
  started_.lap();
  since_draw_.lap();
}

Progress::~Progress() {
  if (finished_) return;
  // Unwinding from an error, or dropped without finish(): show where it stopped, not 100%.
  finished_ = true;
  draw_stopped(std::uncaught_exceptions() > uncaught_ ? "failed" : "stopped");
}

void Progress::advance(uint64_t by) { set(done_ + by); }

void Progress::set(uint64_t done) {
  if (finished_) return;
  done_ = done;
  if (since_draw_.seconds() > 0.1) {
    since_draw_.lap();
    draw(false);
  }
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  done_ = total_;
  draw(true);
}

void Progress::fail() {
  if (finished_) return;
  finished_ = true;
  draw_stopped("failed");
}

std::string Progress::stopped_text(const char* verb, const std::string& unit, uint64_t done, uint64_t total) {
  // Items before `done` are complete; the run stopped in the next one (or after the last).
  const bool after_last = total > 0 && done >= total;
  const uint64_t at = after_last ? total : done + 1;
  return std::string(verb) + (after_last ? " after " : " at ") + (unit.empty() ? "" : unit + " ") + std::to_string(at) +
         "/" + std::to_string(total);
}

void Progress::draw(bool final) {
  if (!enabled_) return;
  const double seconds = started_.seconds();
  const double fraction = total_ ? double(done_) / double(total_) : 1.0;
  std::fprintf(stderr, "\r%-12s [%s] %5.1f%%  %6.1fs  %s\033[K", label_.c_str(), bar_of(done_, total_).c_str(),
               100.0 * fraction, seconds, detail_.c_str());
  if (final) std::fputc('\n', stderr);
  std::fflush(stderr);
}

void Progress::draw_stopped(const char* verb) {
  if (!enabled_) return;
  const double seconds = started_.seconds();
  // No percentage: a stopped run never reads as complete, whatever fraction it reached.
  std::fprintf(stderr, "\r%-12s [%s] %s  %6.1fs\033[K\n", label_.c_str(), bar_of(done_, total_).c_str(),
               stopped_text(verb, unit_, done_, total_).c_str(), seconds);
  std::fflush(stderr);
}

}  // namespace vs
