// view: a browser viewer served by the binary itself. civetweb serves the page (view_page.cpp,
// made from page.html at build time) and one WebSocket per tab: the page sends view and play
// messages (protocol.h), each tab's worker thread renders the newest one and sends the frame as
// one binary message: a 4-byte little-endian length, the frame's JSON description, the JPEG.
#include <civetweb.h>
#include <turbojpeg.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <thread>

#include "commands.h"
#include "render_options.h"
#include "view/protocol.h"
#include "volstream/core/error.h"
#include "volstream/core/stopwatch.h"
#include "volstream/frame/frame_renderer.h"
#include "volstream/io/image.h"
#include "volstream/stream/pipeline.h"
#include "volstream/stream/render_stages.h"
#include "volstream/stream/timeline.h"

namespace vs::cli {
extern const char* const kViewPage;  // view_page.cpp (generated)
}

namespace vs::view {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

constexpr int kJpegQuality = 85;

struct ViewArgs {
  std::string dir, host = "127.0.0.1";
  int port = 8080;
  cli::RenderOptions render;
};

class JpegEncoder {
 public:
  JpegEncoder() : handle_(tjInitCompress()) {
    if (!handle_) throw std::runtime_error("libjpeg-turbo: cannot create a compressor");
  }
  ~JpegEncoder() { tjDestroy(handle_); }
  JpegEncoder(const JpegEncoder&) = delete;
  JpegEncoder& operator=(const JpegEncoder&) = delete;

  std::vector<uint8_t> encode(const std::vector<uint8_t>& rgb, uint32_t width, uint32_t height) {
    unsigned char* out = nullptr;
    unsigned long size = 0;
    if (tjCompress2(handle_, rgb.data(), int(width), 0, int(height), TJPF_RGB, &out, &size, TJSAMP_420, kJpegQuality,
                    TJFLAG_FASTDCT) != 0)
      throw std::runtime_error(std::string("JPEG encoding failed: ") + tjGetErrorStr2(handle_));
    std::vector<uint8_t> bytes(out, out + size);
    tjFree(out);
    return bytes;
  }

 private:
  tjhandle handle_;
};

// What every tab shares: the dataset, one renderer (frames of different tabs take turns) and the
// values behind the last histogram.
class Viewer {
 public:
  Viewer(const ViewArgs& args, const Dataset& ds)
      : dataset_path(args.dir),
        dataset(ds),
        initial{args.render, 0, false},
        renderer_(ds, resolve_device(args.render.device, ds, parse_mesh_encoding(args.render.encoding))) {
    cli::make_render_plan(initial.options, ds, {0});  // bad options: one line before the server starts
  }

  struct Rendered {
    std::vector<uint8_t> rgb;
    FrameReport report;
    std::vector<uint32_t> histogram;
  };
  Rendered render(const ViewFrame& f, bool with_histogram) {
    std::lock_guard lock(mutex_);
    Rendered out;
    const FrameRequest& r = f.plan.request;
    out.rgb = renderer_.render_srgb8(r, f.plan.background, &out.report);
    if (with_histogram) {
      if (values_field_ != r.field || values_step_ != r.step) {
        values_ = dataset.load_values(r.field, r.step);
        values_field_ = r.field;
        values_step_ = r.step;
      }
      out.histogram = histogram(values_, r.tf);
    }
    return out;
  }

  const std::string dataset_path;
  const Dataset& dataset;
  const ViewState initial;

 private:
  std::mutex mutex_;
  FrameRenderer renderer_;
  std::vector<float> values_;
  int values_field_ = -1, values_step_ = -1;
};

// Play through the streaming pipeline (stream/pipeline.h), as `volstream play` does: the tab's
// own renderer and step buffers for the played field, the next step read (and uploaded) while
// this one renders. The pipeline's output stage is `send`: the frame goes to the page.
class Player : public stream::FrameWriter {
 public:
  using Send = std::function<void(const Image&, const PlayMeter&)>;
  Player(const Dataset& ds, const cli::RenderPlan& plan, Send send)
      : field_(plan.request.field),
        send_(std::move(send)),
        stages_(ds, plan.setup(), this),
        timeline_("view play"),
        pipeline_(ds, field_, stream::PipelineFlags::at(kPlayLevel), stages_, &timeline_) {}

  static constexpr stream::Level kPlayLevel = stream::Level::overlap;  // `volstream play`'s default
  int field() const { return field_; }

  // Renders the request's step as the request shows it (the view may have changed since the
  // last frame) and sends it; the pipeline starts loading `next` meanwhile.
  void frame(const FrameRequest& request, int next) {
    stages_.set_request(request);
    pipeline_.advance(frames_++, request.step, next);
  }
  void write(const Image& image, int, int) override {
    meter_.add(timeline_.take_events());
    send_(image, meter_);
  }

 private:
  int field_;
  Send send_;
  stream::RendererStages stages_;
  stream::Timeline timeline_;
  PlayMeter meter_;
  int frames_ = 0;
  stream::Pipeline pipeline_;  // last: destroyed first, waiting for its loader
};

// One browser tab: its state, its mailbox and the worker that renders for it.
class Session {
 public:
  Session(mg_connection* conn, Viewer& viewer) : conn_(conn), viewer_(viewer), state_(viewer.initial) {
    worker_ = std::thread([this] { run(); });
  }
  ~Session() {
    latest_.stop();
    worker_.join();
  }

  // On civetweb's thread: check the message, update the state, wake the worker. While playing,
  // a view change waits for the next play frame, which shows it.
  void on_message(std::string_view text) {
    try {
      const Message m = parse_message(text);
      std::lock_guard lock(mutex_);
      if (m.kind == Message::Kind::view) {
        ViewFrame f = apply_view(state_, m.body, viewer_.dataset);
        state_ = f.state;
        if (play_.on) seeked_ = seeked_ || m.body.contains("step");
        if (!play_.on) latest_.post(std::move(f));
      } else {
        set_play(play_settings(m.body));
      }
    } catch (const std::exception& e) {  // ProtocolError, and anything a bad value provokes
      send_error(e.what());
    }
  }

  void send_error(const std::string& message) { send_text(json{{"type", "error"}, {"message", message}}.dump()); }

 private:
  // Under mutex_. Pausing shows the step played last as a still frame (with its histogram, which
  // play frames leave as it was).
  void set_play(const PlaySettings& p) {
    if (p.on && !play_.on) seeked_ = false;
    if (!p.on && play_.on) {
      state_.preview = false;
      latest_.post(plan_view(state_, viewer_.dataset));
    }
    play_ = p;
  }

  void run() {
    Stopwatch since_frame;
    while (!latest_.stopped()) {
      std::optional<ViewFrame> f = latest_.take(wait_time(since_frame.seconds()));
      if (latest_.stopped()) break;
      if (f) {
        const double interval = since_frame.lap();
        try {
          render_and_send(*f, interval);
        } catch (const std::exception& e) {
          send_error(std::string("render failed: ") + e.what());
        }
      } else if (std::optional<ViewFrame> next = next_play_frame()) {
        since_frame.lap();
        play(*next);
      }
    }
  }

  std::chrono::milliseconds wait_time(double since_frame_s) {
    std::lock_guard lock(mutex_);
    if (!play_.on) return 200ms;
    const double left = 1.0 / play_.fps - since_frame_s;
    return std::chrono::milliseconds(std::max(0, int(left * 1e3)));
  }

  // Playing: the next step (or the one the slider moved to) at the current view; the page's
  // slider follows the frames.
  std::optional<ViewFrame> next_play_frame() {
    std::lock_guard lock(mutex_);
    if (!play_.on) return std::nullopt;
    if (!seeked_) state_.step = (state_.step + 1) % viewer_.dataset.manifest().step_count();
    seeked_ = false;
    state_.preview = false;
    try {
      return plan_view(state_, viewer_.dataset);
    } catch (const std::exception& e) {
      stop_play(e.what());
      return std::nullopt;
    }
  }

  // One frame through the tab's pipeline; another field needs another pipeline (the old one
  // is dropped first: it waits for its loader and frees its buffers). An error stops play.
  void play(const ViewFrame& f) {
    const FrameRequest& r = f.plan.request;
    try {
      if (!player_ || player_->field() != r.field) {
        player_.reset();
        player_ = std::make_unique<Player>(viewer_.dataset, f.plan, [this](const Image& image, const PlayMeter& meter) {
          send_play_frame(image, meter);
        });
      }
      playing_ = &f;
      player_->frame(r, (r.step + 1) % viewer_.dataset.manifest().step_count());
    } catch (const std::exception& e) {
      std::lock_guard lock(mutex_);
      stop_play(e.what());
    }
  }

  // Under mutex_. The page's play button follows "playing".
  void stop_play(const std::string& why) {
    play_.on = false;
    send_text(json{{"type", "error"}, {"message", "play stopped: " + why}, {"playing", false}}.dump());
  }

  // The pipeline's output stage (worker thread, inside Player::frame): the frame of *playing_.
  void send_play_frame(const Image& image, const PlayMeter& meter) {
    const ViewFrame& f = *playing_;
    Stopwatch watch;
    const std::vector<uint8_t> jpeg =
        jpeg_.encode(to_rgb8(image, f.plan.background), f.plan.request.width, f.plan.request.height);
    json header = frame_header(f, true);
    header.update(meter.describe());
    header["encode_ms"] = watch.seconds() * 1e3;
    header["pipeline"] = stream::level_name(Player::kPlayLevel);
    send_frame(header.dump(), jpeg);
  }

  void render_and_send(const ViewFrame& f, double interval_s) {
    const FrameRequest& r = f.plan.request;
    const std::string histogram_key = std::to_string(r.field) + "/" + std::to_string(r.step) + "/" +
                                      std::to_string(r.tf.lo) + "/" + std::to_string(r.tf.hi) +
                                      (r.tf.log_scale ? "/log" : "");
    const bool new_histogram = histogram_key != histogram_key_;
    Stopwatch watch;
    Viewer::Rendered out = viewer_.render(f, new_histogram);
    const double render_s = watch.lap();
    const std::vector<uint8_t> jpeg = jpeg_.encode(out.rgb, r.width, r.height);
    const double encode_s = watch.lap();

    json header = frame_header(f, false);
    header["render_ms"] = render_s * 1e3;
    header["encode_ms"] = encode_s * 1e3;
    header["slowest"] = slowest_of_frame(out.report.seconds, encode_s);
    header["fps"] = 1.0 / std::max(interval_s, 1e-6);
    if (new_histogram) {
      header["histogram"] = out.histogram;
      histogram_key_ = histogram_key;
    }
    send_frame(header.dump(), jpeg);
  }

  // What every frame's header says: the view (describe_frame), its command line, and whether
  // the tab is playing (a play frame says so even when a pause came while it rendered: the
  // still frame the pause asked for follows it).
  json frame_header(const ViewFrame& f, bool play_frame) {
    json header = describe_frame(f.state, f.plan, viewer_.dataset);
    header["type"] = "frame";
    header["command"] = command_line(viewer_.dataset_path, f.state, f.plan);
    std::lock_guard lock(mutex_);
    header["playing"] = play_frame || play_.on;
    return header;
  }

  void send_frame(const std::string& header, const std::vector<uint8_t>& jpeg) {
    std::string message(4, '\0');
    for (int i = 0; i < 4; ++i) message[size_t(i)] = char((header.size() >> (8 * i)) & 0xff);
    message += header;
    message.append(reinterpret_cast<const char*>(jpeg.data()), jpeg.size());
    write(MG_WEBSOCKET_OPCODE_BINARY, message);
  }
  void send_text(const std::string& text) { write(MG_WEBSOCKET_OPCODE_TEXT, text); }
  // Writes come from civetweb's thread (errors) and the worker (frames): one at a time.
  void write(int opcode, const std::string& data) {
    mg_lock_connection(conn_);
    mg_websocket_write(conn_, opcode, data.data(), data.size());
    mg_unlock_connection(conn_);
  }

  mg_connection* conn_;
  Viewer& viewer_;
  std::mutex mutex_;  // state_, play_ and seeked_: civetweb's thread writes, the worker reads
  ViewState state_;
  PlaySettings play_;
  bool seeked_ = false;  // playing: the slider moved, so the next frame shows state_.step
  LatestRequest<ViewFrame> latest_;
  JpegEncoder jpeg_;
  std::string histogram_key_;           // worker only: the histogram the page has
  std::unique_ptr<Player> player_;      // worker only: made at the first play frame
  const ViewFrame* playing_ = nullptr;  // worker only: the frame player_ is rendering
  std::thread worker_;                  // last: starts once everything above exists
};

// The tabs by connection; civetweb's close handler (or the server's end) removes them.
class Sessions {
 public:
  explicit Sessions(Viewer& viewer) : viewer_(viewer) {}
  void open(mg_connection* conn) {
    auto session = std::make_unique<Session>(conn, viewer_);
    std::lock_guard lock(mutex_);
    sessions_[conn] = std::move(session);
  }
  Session* find(const mg_connection* conn) {
    std::lock_guard lock(mutex_);
    auto it = sessions_.find(conn);
    return it == sessions_.end() ? nullptr : it->second.get();
  }
  void close(const mg_connection* conn) {
    std::unique_ptr<Session> closing;
    {
      std::lock_guard lock(mutex_);
      auto it = sessions_.find(conn);
      if (it == sessions_.end()) return;
      closing = std::move(it->second);
      sessions_.erase(it);
    }
    // ~Session joins the worker outside the lock (it may be sending).
  }
  void close_all() {
    std::map<const mg_connection*, std::unique_ptr<Session>> closing;
    std::lock_guard lock(mutex_);
    closing.swap(sessions_);
  }

 private:
  Viewer& viewer_;
  std::mutex mutex_;
  std::map<const mg_connection*, std::unique_ptr<Session>> sessions_;
};

int serve_page(mg_connection* conn, void*) {
  const std::string page = cli::kViewPage;
  mg_send_http_ok(conn, "text/html; charset=utf-8", (long long)page.size());
  mg_write(conn, page.data(), page.size());
  return 200;
}

// 0 accepts the handshake; a page from another origin is refused (websocket_origin_allowed).
int on_ws_connect(const mg_connection* conn, void*) {
  mg_connection* c = const_cast<mg_connection*>(conn);  // civetweb's header lookup takes it non-const
  return websocket_origin_allowed(mg_get_header(c, "Origin"), mg_get_header(c, "Host")) ? 0 : 1;
}
void on_ws_ready(mg_connection* conn, void* sessions) { static_cast<Sessions*>(sessions)->open(conn); }
int on_ws_data(mg_connection* conn, int bits, char* data, size_t size, void* sessions) {
  const int opcode = bits & 0xf;
  if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
  if (opcode == MG_WEBSOCKET_OPCODE_PING || opcode == MG_WEBSOCKET_OPCODE_PONG) return 1;
  Session* session = static_cast<Sessions*>(sessions)->find(conn);
  if (!session) return 0;
  if (opcode == MG_WEBSOCKET_OPCODE_TEXT)
    session->on_message(std::string_view(data, size));
  else
    session->send_error("only JSON text messages are understood");
  return 1;
}
void on_ws_close(const mg_connection* conn, void* sessions) { static_cast<Sessions*>(sessions)->close(conn); }

volatile std::sig_atomic_t g_stop_requested = 0;
void request_stop(int) { g_stop_requested = 1; }

// Ctrl-C (and SIGTERM) end the wait below; the server then closes every tab and returns.
class StopOnSignal {
 public:
  StopOnSignal() {
    g_stop_requested = 0;
    struct sigaction action {};
    action.sa_handler = request_stop;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~StopOnSignal() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  static bool requested() { return g_stop_requested != 0; }

 private:
  struct sigaction old_int_ {
  }, old_term_{};
};

void check_port(int port) {
  if (port < 0 || port > 65535) throw UsageError("--port must be in [0, 65535] (0: any free port)");
}

void run_view(const ViewArgs& a) {
  check_port(a.port);
  const ListenHost host = parse_listen_host(a.host);
  // Debian's libcivetweb (1.15) is built without USE_IPV6: it would refuse [::1]:PORT with a
  // message about the port; say why instead.
  if (host.ipv6 && !mg_check_feature(8 /* MG_FEATURES_IPV6 */))
    throw UsageError("--host " + a.host + ": this build's civetweb has no IPv6 support; use an IPv4 address such as " +
                     "127.0.0.1");
  const Dataset ds(a.dir);
  Viewer viewer(a, ds);
  Sessions sessions(viewer);
  const StopOnSignal stop;

  mg_init_library(0);
  const std::string ports = host_and_port(host, a.port);
  // tcp_nodelay: civetweb writes a WebSocket frame's header and payload with two send() calls;
  // with Nagle's algorithm the payload then waits for the browser's delayed ACK of the header
  // (40 ms on Linux), which was most of the viewer's own share of each frame's latency.
  const char* options[] = {"listening_ports", ports.c_str(), "num_threads", "16", "tcp_nodelay", "1", nullptr};
  mg_callbacks callbacks{};
  callbacks.log_message = [](const mg_connection*, const char*) { return 1; };  // quiet: errors are ours to report
  mg_context* ctx = mg_start(&callbacks, nullptr, options);
  if (!ctx) {
    mg_exit_library();
    throw UsageError("cannot listen on " + ports + " (in use? --port 0 picks a free one)");
  }
  mg_set_request_handler(ctx, "/$", serve_page, nullptr);
  mg_set_websocket_handler(ctx, "/ws$", on_ws_connect, on_ws_ready, on_ws_data, on_ws_close, &sessions);
  mg_server_port bound{};
  mg_get_server_ports(ctx, 1, &bound);
  std::printf("volstream view: %s (Ctrl-C stops; from another machine: ssh -L %d:localhost:%d HOST)\n",
              page_url(host, bound.port).c_str(), bound.port, bound.port);
  std::fflush(stdout);
  while (!StopOnSignal::requested()) std::this_thread::sleep_for(100ms);
  mg_stop(ctx);  // closes the connections (their close handlers end the sessions)
  sessions.close_all();
  mg_exit_library();
  std::printf("volstream view: stopped\n");
}

}  // namespace
}  // namespace vs::view

namespace vs::cli {

void add_view_command(CLI::App& app) {
  auto a = std::make_shared<view::ViewArgs>();
  auto* cmd = app.add_subcommand("view", "Serve an interactive browser viewer of a dataset (open the printed URL)");
  cmd->add_option("dataset", a->dir, "dataset directory")->required();
  cmd->add_option("--port", a->port, "TCP port (0: any free port)")->capture_default_str();
  cmd->add_option("--host", a->host, "address to listen on: IPv4 or IPv6 (0.0.0.0 or ::: every interface)")
      ->capture_default_str();
  add_render_options(cmd, a->render, RenderContext::image);
  cmd->callback([a] { view::run_view(*a); });
}

}  // namespace vs::cli
