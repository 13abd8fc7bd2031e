// The viewer's message protocol, without a socket: what the page may say (JSON text messages),
// checked and turned into the render options the command line takes, so that the page's view,
// `volstream render`'s command line and the frame request come from one set of values. Also the
// histogram under the transfer-function editor and the "newest request wins" mailbox of the
// render loop. The civetweb and JPEG glue is apps/view/server.cpp.
#pragma once
#include <nlohmann/json.hpp>

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "render_options.h"
#include "volstream/io/dataset.h"

namespace vs::view {

// Page messages are small (a camera, a transfer function of at most kMaxOpacityPoints points);
// anything larger is refused before parsing.
inline constexpr size_t kMaxMessageBytes = 64 * 1024;
inline constexpr size_t kMaxOpacityPoints = 64;
inline constexpr uint32_t kMinSide = 16, kMaxSide = 4096;
// Frames while the mouse moves are this many times smaller on each side.
inline constexpr uint32_t kPreviewDivisor = 3;
inline constexpr int kHistogramBins = 256;

// Whether a WebSocket handshake may be accepted: browsers let any page open a socket to
// 127.0.0.1, so a page from elsewhere could drive the viewer and read its frames. Browsers send
// the page's Origin; it must name the host the page was served from (the request's Host header).
// No Origin at all is a client that is not a browser page (a script), which is accepted.
bool websocket_origin_allowed(const char* origin, const char* host);

// A message the page sent that cannot be honoured; its what() goes back to the page.
struct ProtocolError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What one viewer tab shows: the command line's render options (with the page's changes), the
// time step, and whether the frame is a quick preview.
struct ViewState {
  cli::RenderOptions options;
  int step = 0;
  bool preview = false;
};

// A checked message: "view" (any subset of the state's keys), "play" (on, fps).
struct Message {
  enum class Kind { view, play } kind = Kind::view;
  nlohmann::json body;  // the object, keys checked by apply_view / play_settings
};
Message parse_message(std::string_view text);  // ProtocolError: too large, not JSON, unknown type

// The state after a view message, checked against the dataset (field, step, values), and the
// plan that renders it at the size the state asks (smaller for a preview).
struct ViewFrame {
  ViewState state;
  cli::RenderPlan plan;
};
ViewFrame apply_view(const ViewState& state, const nlohmann::json& view, const Dataset& dataset);
ViewFrame plan_view(const ViewState& state, const Dataset& dataset);  // the state as it is

struct PlaySettings {
  bool on = false;
  double fps = 10;
};
PlaySettings play_settings(const nlohmann::json& play);

// `volstream render ...` that reproduces the frame (full size, resolved range and camera).
std::string command_line(const std::string& dataset_path, const ViewState& state, const cli::RenderPlan& plan);
// What the page needs to draw its controls: camera, resolved range and scale.
nlohmann::json describe_frame(const ViewState& state, const cli::RenderPlan& plan, const Dataset& dataset);

// Counts of `values` in `bins` equal parts of the transfer function's (scaled) range; values
// outside it (and <= 0 on a log scale, NaN) are not counted.
std::vector<uint32_t> histogram(const std::vector<float>& values, const TransferFunctionSpec& tf,
                                int bins = kHistogramBins);

// "Newest request wins": a mailbox of one. post() replaces what is waiting, so a render loop
// that falls behind the mouse renders the latest view, never a queue of stale ones.
template <class T>
class LatestRequest {
 public:
  void post(T value) {
    {
      std::lock_guard lock(mutex_);
      pending_ = std::move(value);
    }
    wake_.notify_one();
  }
  // The newest posted value; nullopt after `timeout` or once stopped.
  template <class Duration>
  std::optional<T> take(Duration timeout) {
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, timeout, [&] { return stopped_ || pending_.has_value(); });
    if (stopped_) return std::nullopt;
    std::optional<T> value = std::move(pending_);
    pending_.reset();
    return value;
  }
  void stop() {
    {
      std::lock_guard lock(mutex_);
      stopped_ = true;
    }
    wake_.notify_all();
  }
  bool stopped() const {
    std::lock_guard lock(mutex_);
    return stopped_;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<T> pending_;
  bool stopped_ = false;
};

}  // namespace vs::view
