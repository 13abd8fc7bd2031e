// The JSON a user hands the tool besides datasets: timeline traces (`volstream timeline`, drawn as
// a Gantt chart) and ParaView colour maps (`--tf map.json`). Valid documents of each, one of them
// patched by the input (fuzz_util.h), then both read.
#include <chrono>
#include <fstream>

#include "fuzz_util.h"
#include "volstream/frame/look.h"
#include "volstream/render/optics/transfer_function.h"
#include "volstream/stream/gantt.h"
#include "volstream/stream/timeline.h"

namespace {

constexpr const char* kColorMap = R"([{"Name": "fuzz", "ColorSpace": "RGB",
  "RGBPoints": [0, 0.1, 0.2, 0.3, 0.5, 0.9, 0.5, 0.1, 1, 1, 1, 1],
  "Points": [0, 0, 0.5, 0, 0.4, 0.2, 0.5, 0, 1, 0.8, 0.5, 0]}])";

// A small trace as play writes it: two lanes, every stage, a few steps.
void write_pristine(const std::filesystem::path& dir) {
  using namespace vs::stream;
  Timeline timeline("fuzz");
  const auto t0 = Timeline::Clock::now();
  for (int step = 0; step < 3; ++step)
    for (int s = 0; s < 6; ++s) {
      const auto begin = t0 + std::chrono::microseconds(1000 * step + 100 * s);
      timeline.record(Stage(s), step, s < 2 ? 1 : 0, begin, begin + std::chrono::microseconds(90));
    }
  write_chrome_trace(dir / "pristine_trace.json", {&timeline});
  std::ofstream(dir / "pristine_map.json") << kColorMap;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace vs;
  static const auto dir = fuzz::scratch("json");
  static const bool ready = (write_pristine(dir), true);
  (void)ready;
  if (size > (1 << 16)) return 0;
  const auto trace = dir / "trace.json", map = dir / "map.json";
  fuzz::copy_file_contents(dir / "pristine_trace.json", trace);
  fuzz::copy_file_contents(dir / "pristine_map.json", map);
  if (!fuzz::apply_patch({trace, map}, data, size)) return 0;
  fuzz::expect_clean([&] {
    const auto events = stream::read_chrome_trace(trace);
    (void)stream::gantt_svg(events, {});
  });
  fuzz::expect_clean([&] { (void)load_paraview_color_map(map.string()); });
  return 0;
}
