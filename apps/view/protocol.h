// The viewer's message protocol, without a socket: what the page may say (JSON text messages),
// checked and turned into the render options the command line takes, so that the page's view,
// `volstream render`'s command line and the frame request come from one set of values. Also the
// histogram under the transfer-function editor, the "newest request wins" mailbox of the render
// loop, play's frames/s and slowest stage, and the --host address in URL syntax. The civetweb and
// JPEG glue is apps/view/server.cpp.
#pragma once
#include <nlohmann/json.hpp>

#include <condition_variable>
#include <cstdint>
#include <deque>
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

// --host: an IPv4 address (or a name civetweb resolves, e.g. localhost) or an IPv6 address, with
// or without brackets (::1, [::1], ::). UsageError, one line, for anything else.
struct ListenHost {
  std::string address;  // without brackets
  bool ipv6 = false;
};
ListenHost parse_listen_host(const std::string& host);
// HOST:PORT with an IPv6 address in brackets ([::1]:8080): civetweb's listening_ports syntax,
// the URL's authority and what browsers send as Host (hence the Origin check above).
std::string host_and_port(const ListenHost& host, int port);
std::string page_url(const ListenHost& host, int port);  // http://[::1]:8080/

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

// For the page's frame header, {"stage": "render", "ms": 12.3}: a still frame's slowest stage,
// of the frame renderer's (only those this frame redid) and the JPEG encoding.
nlohmann::json slowest_of_frame(const FrameTimes& times, double encode_s);

// Frames/s and the slowest stage of play from the pipeline's timeline (stream/timeline.h), over
// the last kPlayWindowSeconds: the view changes while playing, and with it the stages' times.
inline constexpr double kPlayWindowSeconds = 2;
class PlayMeter {
 public:
  void add(const std::vector<stream::TimelineEvent>& events);  // as Timeline::take_events() gives them
  double fps() const;                                          // 0 until two frames were output
  // {"fps", "slowest": {"stage", "ms"} (null before any event), "render_ms": the render stage's mean}
  nlohmann::json describe() const;

 private:
  std::deque<stream::TimelineEvent> events_;
};

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
