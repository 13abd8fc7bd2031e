// The viewer's message protocol without a socket: malformed, oversized and out-of-range messages
// are refused with a message (the state stays as it was), good ones become the frame request and
// the command line that reproduces it; the histogram; "newest request wins".
#include "view/protocol.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "test_util.h"
#include "volstream/amr/demo.h"
#include "volstream/core/error.h"
#include "volstream/frame/look.h"

namespace vs::view {
namespace {

using nlohmann::json;

const Dataset& jet() {
  static const Dataset ds = [] {
    const auto dir = test::scratch_dir("view_protocol_jet");
    auto source = make_demo({"jet", 20000, 3});
    convert_to_dataset(*source, dir, ConvertOptions::silent());
    return Dataset(dir);
  }();
  return ds;
}

ViewState initial() {
  ViewState s;
  s.options.size = "320x200";
  return s;
}

ViewFrame apply(const std::string& text, const ViewState& state = initial()) {
  const Message m = parse_message(text);
  EXPECT_EQ(m.kind, Message::Kind::view);
  return apply_view(state, m.body, jet());
}

std::string refusal(const std::string& text) {
  try {
    apply(text);
  } catch (const ProtocolError& e) {
    return e.what();
  }
  return "";
}

TEST(ViewProtocol, RefusesMalformedMessages) {
  for (const char* text :
       {"", "{", "[1,2]", "42", "{\"type\":3}", "{\"no_type\":1}", "{\"type\":\"explode\"}", "\xff\xfe garbage"})
    EXPECT_THROW(parse_message(text), ProtocolError) << text;
}

TEST(ViewProtocol, RefusesOversizedMessages) {
  const std::string big = "{\"type\":\"view\",\"pad\":\"" + std::string(kMaxMessageBytes, 'x') + "\"}";
  try {
    parse_message(big);
    FAIL() << "accepted";
  } catch (const ProtocolError& e) {
    EXPECT_NE(std::string(e.what()).find("too large"), std::string::npos);
  }
}

TEST(ViewProtocol, RefusesOutOfRangeValues) {
  const char* bad[] = {
      R"({"type":"view","step":-1})",
      R"({"type":"view","step":3})",  // the demo has steps 0..2
      R"({"type":"view","step":1.5})",
      R"({"type":"view","step":"1"})",
      R"({"type":"view","field":"nope"})",
      R"({"type":"view","field":7})",
      R"({"type":"view","tf":"/etc/passwd"})",
      R"({"type":"view","tf":"nosuchmap"})",
      R"({"type":"view","log":1})",
      R"({"type":"view","range":[2,1]})",
      R"({"type":"view","range":[1]})",
      R"({"type":"view","range":[0,1e999]})",
      R"({"type":"view","width":0})",
      R"({"type":"view","width":100000})",
      R"({"type":"view","height":7.5})",
      R"({"type":"view","opacity":[[0,0.1,3]]})",
      R"({"type":"view","opacity":[[0,-1]]})",
      R"({"type":"view","opacity":"0:1"})",
      R"({"type":"view","iso":[1,2,3,4,5,6,7,8,9]})",
      R"({"type":"view","camera":{"pos":[0,0,0],"at":[0,0,0],"up":[0,1,0]}})",  // degenerate
      R"({"type":"view","camera":{"pos":[1,2,3]}})",
      R"({"type":"view","camera":{"pos":[1,2,3],"at":[0,0,0],"up":[0,1,0],"fov":400}})",
      R"({"type":"view","camera":{"pos":[1,2,"x"],"at":[0,0,0],"up":[0,1,0]}})",
      R"({"type":"view","camera":5})",
  };
  for (const char* text : bad) EXPECT_FALSE(refusal(text).empty()) << text;
}

TEST(ViewProtocol, RefusesBadPlaySettings) {
  EXPECT_THROW(play_settings(json{{"on", "yes"}}), ProtocolError);
  EXPECT_THROW(play_settings(json{{"on", true}, {"fps", 0}}), ProtocolError);
  EXPECT_THROW(play_settings(json{{"on", true}, {"fps", 1e9}}), ProtocolError);
  EXPECT_TRUE(play_settings(json{{"on", true}, {"fps", 5}}).on);
}

TEST(ViewProtocol, AppliesAViewAndLeavesTheRestAsItWas) {
  const ViewFrame f = apply(
      R"({"type":"view","step":2,"tf":"inferno","range":[0.5,2],"opacity":[[0.5,0],[2,0.8]],"iso":[1.5],
          "camera":{"pos":[3,2,1],"at":[0,0,0],"up":[0,0,1],"fov":50},"width":640,"height":360})");
  const FrameRequest& r = f.plan.request;
  EXPECT_EQ(r.step, 2);
  EXPECT_EQ(r.width, 640u);
  EXPECT_EQ(r.height, 360u);
  EXPECT_FLOAT_EQ(r.tf.lo, 0.5f);
  EXPECT_FLOAT_EQ(r.tf.hi, 2.f);
  EXPECT_EQ(r.integrator.iso_count, 1u);
  EXPECT_EQ(r.camera.position.x, 3);
  EXPECT_EQ(r.camera.fov_deg, 50);
  // A later message changes only what it names.
  const ViewFrame g = apply(R"({"type":"view","step":1})", f.state);
  EXPECT_EQ(g.plan.request.step, 1);
  EXPECT_FLOAT_EQ(g.plan.request.tf.lo, 0.5f);
  EXPECT_EQ(g.plan.request.camera.position.x, 3);
  // The default view again (reset), and a preview at a third of the size.
  const ViewFrame h = apply(R"({"type":"view","camera":null,"preview":true})", g.state);
  EXPECT_EQ(h.plan.request.camera.position.x, default_view(jet(), 640, 360).position.x);
  EXPECT_EQ(h.plan.request.width, 640u / kPreviewDivisor);
}

TEST(ViewProtocol, CommandLineReproducesTheView) {
  const ViewFrame f = apply(R"({"type":"view","step":1,"tf":"viridis","log":true,"iso":[1.25],
      "camera":{"pos":[3,2,1],"at":[0.5,0,0],"up":[0,1,0],"fov":40}})");
  const std::string cmd = command_line("runs/jet", f.state, f.plan);
  for (const char* part :
       {"volstream render 'runs/jet' --step 1", "--tf viridis --log", "--iso 1.25", "--camera-pos 3,2,1",
        "--camera-at 0.5,0,0", "--camera-up 0,1,0", "--fov 40", "--size 320x200", "--range "})
    EXPECT_NE(cmd.find(part), std::string::npos) << part << " not in " << cmd;
}

TEST(ViewProtocol, DescribesTheFrameForThePage) {
  const ViewFrame f = apply(R"({"type":"view"})");
  const json d = describe_frame(f.state, f.plan, jet());
  EXPECT_EQ(d["steps"], 3);
  EXPECT_EQ(d["fields"].size(), jet().manifest().fields.size());
  EXPECT_GE(d["opacity"].size(), 2u);  // the default ramp's points, to edit
  EXPECT_EQ(d["camera"]["pos"].size(), 3u);
}

TEST(ViewProtocol, HistogramCountsValuesInTheRange) {
  TransferFunctionSpec tf;
  tf.lo = 0;
  tf.hi = 4;
  const auto counts = histogram({0.f, 0.5f, 1.f, 3.99f, 4.f, 5.f, -1.f, NAN}, tf, 4);
  EXPECT_EQ(counts, (std::vector<uint32_t>{2, 1, 0, 2}));
  tf.log_scale = true;
  tf.lo = 1;
  tf.hi = 100;
  EXPECT_EQ(histogram({0.f, 1.f, 5.f, 50.f, 100.f}, tf, 2), (std::vector<uint32_t>{2, 2}));
}

// A page from another site must not open a socket to the viewer; its own page and non-browser
// clients (no Origin) may.
TEST(ViewProtocol, WebSocketsOnlyFromTheViewersOwnPage) {
  EXPECT_TRUE(websocket_origin_allowed("http://127.0.0.1:8080", "127.0.0.1:8080"));
  EXPECT_TRUE(websocket_origin_allowed("http://localhost:9000", "localhost:9000"));
  EXPECT_TRUE(websocket_origin_allowed(nullptr, "127.0.0.1:8080"));
  EXPECT_FALSE(websocket_origin_allowed("http://evil.example", "127.0.0.1:8080"));
  EXPECT_FALSE(websocket_origin_allowed("http://127.0.0.1:8081", "127.0.0.1:8080"));
  EXPECT_FALSE(websocket_origin_allowed("https://127.0.0.1:8080", "127.0.0.1:8080"));
  EXPECT_FALSE(websocket_origin_allowed("null", "127.0.0.1:8080"));
  EXPECT_FALSE(websocket_origin_allowed("http://127.0.0.1:8080", nullptr));
}

// The page of a viewer on an IPv6 address is at http://[::1]:PORT, and browsers send that
// bracketed form as both Host and Origin.
TEST(ViewProtocol, WebSocketsFromTheOwnPageOverIPv6) {
  EXPECT_TRUE(websocket_origin_allowed("http://[::1]:8080", "[::1]:8080"));
  EXPECT_FALSE(websocket_origin_allowed("http://[::1]:8081", "[::1]:8080"));
  EXPECT_FALSE(websocket_origin_allowed("http://127.0.0.1:8080", "[::1]:8080"));
  EXPECT_FALSE(websocket_origin_allowed("http://[::2]:8080", "[::1]:8080"));
}

TEST(ViewProtocol, ListenHostsInUrlSyntax) {
  const ListenHost v4 = parse_listen_host("127.0.0.1");
  EXPECT_FALSE(v4.ipv6);
  EXPECT_EQ(host_and_port(v4, 8080), "127.0.0.1:8080");
  EXPECT_EQ(page_url(v4, 8080), "http://127.0.0.1:8080/");
  for (const char* text : {"::1", "[::1]"}) {
    const ListenHost v6 = parse_listen_host(text);
    EXPECT_TRUE(v6.ipv6) << text;
    EXPECT_EQ(v6.address, "::1");
    EXPECT_EQ(host_and_port(v6, 8080), "[::1]:8080");  // civetweb's listening_ports syntax
    EXPECT_EQ(page_url(v6, 8080), "http://[::1]:8080/");
  }
  EXPECT_EQ(page_url(parse_listen_host("::"), 9), "http://[::]:9/");
  EXPECT_EQ(page_url(parse_listen_host("fe80::1:2"), 80), "http://[fe80::1:2]:80/");
  EXPECT_EQ(parse_listen_host("localhost").address, "localhost");  // civetweb resolves names
  for (const char* bad : {"", "1.2.3.4,5", "::1::2", "[::1", "::1]", "[127.0.0.1]", "[]", "::g", "127.0.0.1:80", "a b",
                          "[::1]:8080", "fe80::1%eth0"}) {
    try {
      parse_listen_host(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const UsageError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("--host expects"), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;  // one line
    }
  }
}

TEST(ViewProtocol, SlowestStageOfAStillFrame) {
  FrameTimes t;
  t.read = 0.004;
  t.classify = 0.002;
  t.refit = 0.003;
  t.render = 0.001;
  EXPECT_EQ(slowest_of_frame(t, 0.0005)["stage"], "refit");  // classify and refit together: 5 ms
  EXPECT_NEAR(slowest_of_frame(t, 0.0005)["ms"].get<double>(), 5.0, 1e-9);
  EXPECT_EQ(slowest_of_frame(t, 0.006)["stage"], "encode");
}

// Play's meter over the pipeline's timeline: output events make the frame rate, the stage with
// the longest mean is the slowest, and only the last kPlayWindowSeconds count.
TEST(PlayMeter, FramesPerSecondAndSlowestStageOverTheWindow) {
  using stream::Stage;
  constexpr int64_t ms = 1000000;
  auto frame = [&](int i, double read_ms, double render_ms) {
    const int64_t t = i * 100 * ms;  // 10 frames/s
    return std::vector<stream::TimelineEvent>{{Stage::read, i + 1, stream::kPrefetchLane, t, t + int64_t(read_ms * ms)},
                                              {Stage::render, i, stream::kFrameLane, t, t + int64_t(render_ms * ms)},
                                              {Stage::output, i, stream::kFrameLane, t + 90 * ms, t + 95 * ms}};
  };
  PlayMeter meter;
  EXPECT_EQ(meter.fps(), 0);
  EXPECT_TRUE(meter.describe()["slowest"].is_null());
  meter.add(frame(0, 10, 40));
  EXPECT_EQ(meter.fps(), 0);  // one frame: no interval yet
  for (int i = 1; i < 10; ++i) meter.add(frame(i, 10, 40));
  EXPECT_NEAR(meter.fps(), 10, 1e-6);
  json d = meter.describe();
  EXPECT_EQ(d["slowest"]["stage"], "render");
  EXPECT_NEAR(d["slowest"]["ms"].get<double>(), 40, 1e-6);
  EXPECT_NEAR(d["render_ms"].get<double>(), 40, 1e-6);
  // Reads get slow: once the fast frames are older than the window, read is the slowest.
  for (int i = 10; i < 40; ++i) meter.add(frame(i, 70, 40));
  d = meter.describe();
  EXPECT_EQ(d["slowest"]["stage"], "read");
  EXPECT_NEAR(d["slowest"]["ms"].get<double>(), 70, 1e-6);
  EXPECT_NEAR(d["fps"].get<double>(), 10, 1e-6);
}

TEST(LatestRequest, KeepsOnlyTheNewest) {
  LatestRequest<int> latest;
  for (int i = 0; i < 5; ++i) latest.post(i);
  EXPECT_EQ(latest.take(std::chrono::milliseconds(0)), 4);
  EXPECT_EQ(latest.take(std::chrono::milliseconds(1)), std::nullopt);
}

TEST(LatestRequest, StopWakesAWaitingTaker) {
  LatestRequest<int> latest;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    latest.stop();
  });
  EXPECT_EQ(latest.take(std::chrono::seconds(30)), std::nullopt);
  EXPECT_TRUE(latest.stopped());
  stopper.join();
}

}  // namespace
}  // namespace vs::view
