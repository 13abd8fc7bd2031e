// The viewer's page messages (apps/view/protocol.h): what a page (or anyone who can reach the
// socket) sends goes through the checks the server runs, and a view that passes them is planned,
// described, turned into a command line and rendered, with its histogram, as the server does. A
// ProtocolError is the expected refusal; anything else aborts.
//
// Byte 0 even: the rest is the message as it is. Odd: the rest patches one of a few valid
// messages (byte 1 picks it, byte 2 the offset), so the fuzzer starts from the page's own words.
#include <string>

#include "fuzz_util.h"
#include "view/protocol.h"
#include "volstream/amr/demo.h"
#include "volstream/frame/frame_renderer.h"

namespace {

using namespace vs;

const char* const kMessages[] = {
    R"({"type":"view","camera":{"pos":[30,20,40],"at":[8,0,0],"up":[0,1,0],"fov":35},"width":40,"height":30})",
    R"({"type":"view","field":"pressure","tf":"inferno","log":false,"range":[-100,50],"step":1,"preview":true})",
    R"({"type":"view","opacity":[[1,0],[10,0.2],[1000,0.9]],"log":true,"iso":[5,50],"width":32,"height":32})",
    R"({"type":"play","on":true,"fps":12})",
};

const Dataset& jet() {
  static const Dataset ds = [] {
    const auto dir = fuzz::scratch("view_protocol") / "jet";
    auto source = make_demo({"jet", 3000, 2});
    convert_to_dataset(*source, dir, ConvertOptions::silent());
    return Dataset(dir);
  }();
  return ds;
}

view::ViewState initial() {
  view::ViewState s;
  s.options.size = "24x16";
  s.options.device = "cpu";
  return s;
}

// What the server does with a view it accepted (apps/view/server.cpp), small frames only: the
// checks allow up to 4096x4096, which would only make the fuzzer slow.
void show(const view::ViewFrame& f) {
  static FrameRenderer renderer(jet(), Device::cpu);
  (void)view::describe_frame(f.state, f.plan, jet());
  (void)view::command_line("ds", f.state, f.plan);
  const FrameRequest& r = f.plan.request;
  if (uint64_t(r.width) * r.height > 64 * 64) return;
  (void)renderer.render_srgb8(r, f.plan.background);
  (void)view::histogram(jet().load_values(r.field, r.step), r.tf);
}

void handle(const std::string& text) {
  try {
    const view::Message m = view::parse_message(text);
    if (m.kind == view::Message::Kind::play)
      (void)view::play_settings(m.body);
    else
      show(view::apply_view(initial(), m.body, jet()));
  } catch (const view::ProtocolError&) {  // refused with a message to the page: fine
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > view::kMaxMessageBytes + 16) return 0;
  std::string text;
  if (data[0] % 2 == 0) {
    text.assign((const char*)data + 1, size - 1);
  } else {
    if (size < 3) return 0;
    text = kMessages[data[1] % std::size(kMessages)];
    const size_t at = data[2] % (text.size() + 1);
    text.replace(at, std::min(size - 3, text.size() - at), (const char*)data + 3, size - 3);
  }
  fuzz::expect_clean([&] { handle(text); });
  return 0;
}
