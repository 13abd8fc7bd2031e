#include "view/protocol.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "volstream/core/error.h"

namespace vs::view {
namespace {

using nlohmann::json;

// Numbers go through the command line's own option strings, so the same checks apply and the
// command line shown to the user is exactly what was rendered. %.9g keeps floats exact.
std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", v);
  return text;
}

std::string join_numbers(const std::vector<double>& values, char sep = ',') {
  std::string text;
  for (double v : values) text += (text.empty() ? "" : std::string(1, sep)) + number_text(v);
  return text;
}

const json& member(const json& object, const char* key, json::value_t type, const char* type_name) {
  const json& value = object.at(key);
  const bool number_ok = type == json::value_t::number_float && value.is_number();
  if (value.type() != type && !number_ok) throw ProtocolError(std::string("'") + key + "' must be " + type_name);
  return value;
}

double finite_number(const json& value, const std::string& what) {
  if (!value.is_number()) throw ProtocolError("'" + what + "' must be a number");
  const double v = value.get<double>();
  if (!std::isfinite(v) || std::abs(v) > 1e30) throw ProtocolError("'" + what + "' must be a finite number");
  return v;
}

std::vector<double> number_array(const json& value, const std::string& what, size_t min_count, size_t max_count) {
  if (!value.is_array() || value.size() < min_count || value.size() > max_count)
    throw ProtocolError("'" + what + "' must be an array of " + std::to_string(min_count) + ".." +
                        std::to_string(max_count) + " numbers");
  std::vector<double> numbers;
  for (const json& v : value) numbers.push_back(finite_number(v, what));
  return numbers;
}

uint32_t side(const json& value, const char* what) {
  const double v = finite_number(value, what);
  if (v != std::floor(v) || v < kMinSide || v > kMaxSide)
    throw ProtocolError(std::string("'") + what + "' must be an integer in [" + std::to_string(kMinSide) + ", " +
                        std::to_string(kMaxSide) + "]");
  return uint32_t(v);
}

// Only built-in colour maps: the option also takes a file path, which a page must not choose.
std::string color_map(const json& value) {
  if (!value.is_string()) throw ProtocolError("'tf' must be a colour map name");
  const std::string name = value.get<std::string>();
  const auto names = builtin_color_map_names();
  if (name != "auto" && std::find(names.begin(), names.end(), name) == names.end())
    throw ProtocolError("unknown colour map '" + name.substr(0, 64) + "'");
  return name;
}

std::string opacity_points(const json& value) {
  if (!value.is_array() || value.size() > kMaxOpacityPoints)
    throw ProtocolError("'opacity' must be an array of at most " + std::to_string(kMaxOpacityPoints) +
                        " [value, alpha] pairs");
  std::string text;
  for (const json& point : value) {
    const auto pair = number_array(point, "opacity", 2, 2);
    if (pair[1] < 0 || pair[1] > 1000) throw ProtocolError("opacity alpha must be in [0, 1000]");
    text += (text.empty() ? "" : ",") + number_text(pair[0]) + ":" + number_text(pair[1]);
  }
  return text;
}

void apply_camera(const json& value, cli::RenderOptions& o) {
  if (value.is_null()) {  // the default view (reset)
    o.camera_pos.clear();
    o.camera_at.clear();
    o.camera_up.clear();
    return;
  }
  if (!value.is_object()) throw ProtocolError("'camera' must be an object or null");
  o.camera_pos = join_numbers(number_array(value.at("pos"), "camera.pos", 3, 3));
  o.camera_at = join_numbers(number_array(value.at("at"), "camera.at", 3, 3));
  o.camera_up = join_numbers(number_array(value.at("up"), "camera.up", 3, 3));
  if (value.contains("fov")) o.fov = finite_number(value["fov"], "camera.fov");
}

void apply_size(const json& view, ViewState& s) {
  uint32_t width = 0, height = 0;
  cli::parse_size(s.options.size, width, height);
  if (view.contains("width")) width = side(view["width"], "width");
  if (view.contains("height")) height = side(view["height"], "height");
  s.options.size = std::to_string(width) + "x" + std::to_string(height);
}

void apply_keys(const json& view, const Dataset& ds, ViewState& s) {
  cli::RenderOptions& o = s.options;
  if (view.contains("field")) o.field = member(view, "field", json::value_t::string, "a field name").get<std::string>();
  if (view.contains("step")) {
    const double step = finite_number(view["step"], "step");
    if (step != std::floor(step) || step < 0 || step >= ds.manifest().step_count())
      throw ProtocolError("'step' must be an integer in [0, " + std::to_string(ds.manifest().step_count() - 1) + "]");
    s.step = int(step);
  }
  if (view.contains("tf")) o.tf = color_map(view["tf"]);
  if (view.contains("log")) o.log = member(view, "log", json::value_t::boolean, "true or false").get<bool>();
  if (view.contains("range"))
    o.range = view["range"].is_null() ? "" : join_numbers(number_array(view["range"], "range", 2, 2));
  if (view.contains("opacity")) o.opacity = opacity_points(view["opacity"]);
  if (view.contains("iso")) o.iso = join_numbers(number_array(view["iso"], "iso", 0, kMaxIso));
  if (view.contains("camera")) apply_camera(view["camera"], o);
  if (view.contains("preview"))
    s.preview = member(view, "preview", json::value_t::boolean, "true or false").get<bool>();
  apply_size(view, s);
}

}  // namespace

Message parse_message(std::string_view text) {
  if (text.size() > kMaxMessageBytes)
    throw ProtocolError("message too large (" + std::to_string(text.size()) + " bytes, at most " +
                        std::to_string(kMaxMessageBytes) + ")");
  Message m;
  m.body = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (m.body.is_discarded()) throw ProtocolError("message is not JSON");
  if (!m.body.is_object() || !m.body.contains("type") || !m.body["type"].is_string())
    throw ProtocolError("message must be an object with a string 'type'");
  const std::string type = m.body["type"].get<std::string>();
  if (type == "view")
    m.kind = Message::Kind::view;
  else if (type == "play")
    m.kind = Message::Kind::play;
  else
    throw ProtocolError("unknown message type '" + type.substr(0, 32) + "'");
  return m;
}

ViewFrame plan_view(const ViewState& state, const Dataset& dataset) {
  ViewFrame f{state, {}};
  cli::RenderOptions options = state.options;
  if (state.preview) {
    uint32_t width = 0, height = 0;
    cli::parse_size(options.size, width, height);
    options.size = std::to_string(std::max(1u, width / kPreviewDivisor)) + "x" +
                   std::to_string(std::max(1u, height / kPreviewDivisor));
  }
  try {
    f.plan = cli::make_render_plan(options, dataset, {state.step});
  } catch (const UsageError& e) {  // the command line's checks: unknown field, degenerate camera, ...
    throw ProtocolError(e.what());
  }
  f.plan.request.step = state.step;
  return f;
}

ViewFrame apply_view(const ViewState& state, const nlohmann::json& view, const Dataset& dataset) {
  ViewState next = state;
  try {
    apply_keys(view, dataset, next);
  } catch (const json::exception&) {  // a missing key inside an object, e.g. camera.pos
    throw ProtocolError("malformed view message (camera needs pos, at and up)");
  } catch (const UsageError& e) {
    throw ProtocolError(e.what());
  }
  return plan_view(next, dataset);
}

PlaySettings play_settings(const nlohmann::json& play) {
  PlaySettings p;
  if (play.contains("on")) {
    if (!play["on"].is_boolean()) throw ProtocolError("'on' must be true or false");
    p.on = play["on"].get<bool>();
  }
  if (play.contains("fps")) p.fps = finite_number(play["fps"], "fps");
  if (!(p.fps >= 0.1 && p.fps <= 120)) throw ProtocolError("'fps' must be in [0.1, 120]");
  return p;
}

std::string command_line(const std::string& dataset_path, const ViewState& state, const cli::RenderPlan& plan) {
  const cli::RenderOptions& o = state.options;
  const FrameRequest& r = plan.request;
  const Camera& c = r.camera;
  const auto& m = state.options;
  std::string cmd = "volstream render '" + dataset_path + "' --step " + std::to_string(state.step);
  if (!m.field.empty()) cmd += " --field " + m.field;
  cmd += " --tf " + o.tf + (o.log ? " --log" : "");
  cmd += " --range " + join_numbers({r.tf.lo, r.tf.hi});
  if (!o.opacity.empty()) cmd += " --opacity " + o.opacity;
  if (!o.iso.empty()) cmd += " --iso " + o.iso;
  cmd += " --camera-pos " + join_numbers({c.position.x, c.position.y, c.position.z});
  cmd += " --camera-at " + join_numbers({c.look_at.x, c.look_at.y, c.look_at.z});
  cmd += " --camera-up " + join_numbers({c.up.x, c.up.y, c.up.z});
  cmd += " --fov " + number_text(c.fov_deg) + " --size " + o.size + " -o view.png";
  return cmd;
}

nlohmann::json describe_frame(const ViewState& state, const cli::RenderPlan& plan, const Dataset& dataset) {
  const FrameRequest& r = plan.request;
  const Camera& c = r.camera;
  json fields = json::array();
  for (const FieldInfo& f : dataset.manifest().fields) fields.push_back(f.name);
  json opacity = json::array();
  // Empty means the table's default ramp: the page edits the points it is shown.
  for (const OpacityPoint& p : r.tf.opacity.empty() ? default_opacity_ramp() : r.tf.opacity)
    opacity.push_back({p.x, p.a});
  json iso = json::array();
  for (uint32_t i = 0; i < r.integrator.iso_count; ++i) iso.push_back(r.integrator.iso[i]);
  return {{"step", state.step},
          {"steps", dataset.manifest().step_count()},
          {"field", dataset.manifest().fields[size_t(r.field)].name},
          {"fields", fields},
          {"color_maps", builtin_color_map_names()},
          {"tf", state.options.tf},
          {"log", r.tf.log_scale},
          {"lo", r.tf.lo},
          {"hi", r.tf.hi},
          {"opacity", opacity},  // normalised positions over [lo, hi] (scaled)
          {"iso", iso},
          {"camera",
           {{"pos", {c.position.x, c.position.y, c.position.z}},
            {"at", {c.look_at.x, c.look_at.y, c.look_at.z}},
            {"up", {c.up.x, c.up.y, c.up.z}},
            {"fov", c.fov_deg}}},
          {"width", r.width},
          {"height", r.height},
          {"preview", state.preview}};
}

std::vector<uint32_t> histogram(const std::vector<float>& values, const TransferFunctionSpec& tf, int bins) {
  std::vector<uint32_t> counts(size_t(std::max(bins, 1)), 0);
  const auto scaled = [&](double v) { return tf.log_scale ? (v > 0 ? std::log10(v) : NAN) : v; };
  const double lo = scaled(tf.lo), hi = scaled(tf.hi);
  if (!(hi > lo)) return counts;
  const double per_unit = double(counts.size()) / (hi - lo);
  for (float v : values) {
    const double x = (scaled(v) - lo) * per_unit;
    if (x >= 0 && x <= double(counts.size())) ++counts[std::min(size_t(x), counts.size() - 1)];
  }
  return counts;
}

bool websocket_origin_allowed(const char* origin, const char* host) {
  if (!origin) return true;
  if (!host || !*host) return false;
  // Origin is scheme://host[:port] with no path; the viewer serves plain http.
  return std::string_view(origin) == std::string("http://") + host;
}

ListenHost parse_listen_host(const std::string& host) {
  const std::string usage =
      "--host expects an IPv4 address such as 127.0.0.1 or 0.0.0.0, or an IPv6 one such as ::1 or ::";
  ListenHost out{host, false};
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') out.address = host.substr(1, host.size() - 2);
  if (out.address.find(':') != std::string::npos) {
    in6_addr parsed{};
    if (inet_pton(AF_INET6, out.address.c_str(), &parsed) != 1) throw UsageError(usage + " (got '" + host + "')");
    out.ipv6 = true;
    return out;
  }
  // IPv4 or a name: civetweb parses it; what would break its comma-separated port list is refused.
  if (out.address != host || host.empty() || host.find_first_of(" ,[]") != std::string::npos)
    throw UsageError(usage + " (got '" + host + "')");
  return out;
}

std::string host_and_port(const ListenHost& host, int port) {
  const std::string address = host.ipv6 ? "[" + host.address + "]" : host.address;
  return address + ":" + std::to_string(port);
}

std::string page_url(const ListenHost& host, int port) { return "http://" + host_and_port(host, port) + "/"; }

nlohmann::json slowest_of_frame(const FrameTimes& t, double encode_s) {
  const std::pair<const char*, double> stages[] = {{"read", t.read},     {"upload", t.upload},
                                                   {"ranges", t.ranges}, {"refit", t.classify + t.refit},
                                                   {"render", t.render}, {"encode", encode_s}};
  const auto* slowest = &stages[0];
  for (const auto& s : stages)
    if (s.second > slowest->second) slowest = &s;
  return {{"stage", slowest->first}, {"ms", slowest->second * 1e3}};
}

void PlayMeter::add(const std::vector<stream::TimelineEvent>& events) {
  int64_t newest = 0;
  events_.insert(events_.end(), events.begin(), events.end());
  for (const stream::TimelineEvent& e : events_) newest = std::max(newest, e.end_ns);
  const auto cutoff = newest - int64_t(kPlayWindowSeconds * 1e9);
  std::erase_if(events_, [&](const stream::TimelineEvent& e) { return e.end_ns < cutoff; });
}

double PlayMeter::fps() const {
  int frames = 0;
  int64_t first = 0, last = 0;
  for (const stream::TimelineEvent& e : events_) {
    if (e.stage != stream::Stage::output) continue;
    first = frames++ ? std::min(first, e.end_ns) : e.end_ns;
    last = std::max(last, e.end_ns);
  }
  return frames >= 2 && last > first ? double(frames - 1) / (double(last - first) * 1e-9) : 0.0;
}

nlohmann::json PlayMeter::describe() const {
  const std::vector<stream::StageSummary> summary = stream::summarize({events_.begin(), events_.end()});
  const stream::StageSummary* slowest = stream::slowest_stage(summary);
  double render_ms = 0;
  for (const stream::StageSummary& s : summary)
    if (s.stage == stream::Stage::render) render_ms = s.mean_ms;
  return {{"fps", fps()},
          {"slowest", slowest ? json{{"stage", stream::stage_name(slowest->stage)}, {"ms", slowest->mean_ms}} : json()},
          {"render_ms", render_ms}};
}

}  // namespace vs::view
