#include "volstream/stream/render_stages.h"

#include <sys/wait.h>

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "volstream/core/error.h"
#include "volstream/cuda/backend.h"
#include "volstream/io/atomic_file.h"
#include "volstream/io/binary_file.h"

namespace vs::stream {

// ---------------------------------------------------------------------------------------------
namespace {
// The one "%[0][width]d" of a pattern ("%%" is a literal percent sign).
struct Conversion {
  size_t begin = std::string::npos, end = 0;
  bool zero = false;
  int width = 0;
};

Conversion find_conversion(const std::string& p) {
  Conversion c;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p[i] != '%') continue;
    if (i + 1 < p.size() && p[i + 1] == '%') {
      ++i;
      continue;
    }
    if (c.begin != std::string::npos) throw UsageError("-o " + p + ": more than one %d");
    c.begin = i++;
    c.zero = i < p.size() && p[i] == '0';
    while (i < p.size() && std::isdigit(static_cast<unsigned char>(p[i]))) c.width = c.width * 10 + (p[i++] - '0');
    if (i >= p.size() || p[i] != 'd' || c.width > 12) throw UsageError("-o " + p + ": only %d, %0Nd and %% may appear");
    c.end = i + 1;
  }
  if (c.begin == std::string::npos)
    throw UsageError("-o " + p + ": a PNG sequence needs a %d for the frame number (frames_%04d.png)");
  return c;
}

std::string unescape_percent(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    out += s[i];
    if (s[i] == '%' && i + 1 < s.size() && s[i + 1] == '%') ++i;
  }
  return out;
}
}  // namespace

std::string PngSequenceWriter::format(const std::string& pattern, int frame) {
  const Conversion c = find_conversion(pattern);
  std::string number = std::to_string(frame);
  if (int(number.size()) < c.width) number.insert(0, size_t(c.width) - number.size(), c.zero ? '0' : ' ');
  return unescape_percent(pattern.substr(0, c.begin)) + number + unescape_percent(pattern.substr(c.end));
}

PngSequenceWriter::PngSequenceWriter(std::string pattern, vec3f background)
    : pattern_(std::move(pattern)), background_(background) {
  find_conversion(pattern_);  // reject a bad pattern before the first frame
  check_output_directory(format(pattern_, 0));
}

void PngSequenceWriter::write(const Image& image, int frame, int) {
  ImageWriteOptions options;
  options.background = background_;
  write_png(image, format(pattern_, frame), options);  // atomic: no partial frame
}

// ---------------------------------------------------------------------------------------------
bool is_video_path(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".mp4" || ext == ".mkv" || ext == ".mov";
}

namespace {
std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool ffmpeg_on_path() {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  for (size_t begin = 0; begin <= dirs.size();) {
    const size_t end = std::min(dirs.find(':', begin), dirs.size());
    const std::string dir = end > begin ? dirs.substr(begin, end - begin) : ".";
    if (::access((dir + "/ffmpeg").c_str(), X_OK) == 0) return true;
    begin = end + 1;
  }
  return false;
}

// ffmpeg's muxer for an extension (the temporary name does not end in it).
const char* muxer(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".mkv" ? "matroska" : ext == ".mov" ? "mov" : "mp4";
}

// The last non-empty line of a small text file ("" if none).
std::string last_line(const std::filesystem::path& file) {
  std::string text, line, last;
  try {
    text = read_text_file(file, 1 << 20);
  } catch (const InputError&) {
    return "";
  }
  for (size_t begin = 0; begin < text.size();) {
    const size_t end = std::min(text.find('\n', begin), text.size());
    if (end > begin) last = text.substr(begin, end - begin);
    begin = end + 1;
  }
  return last;
}
}  // namespace

// ffmpeg writes to a temporary name beside the video and its messages to another; finish()
// renames the video into place only if ffmpeg took every frame, said nothing and exited 0.
VideoWriter::VideoWriter(std::string path, uint32_t width, uint32_t height, double fps, vec3f background)
    : path_(std::move(path)), width_(width), height_(height), background_(background) {
  if (!(fps > 0 && fps <= 1000)) throw UsageError("--fps must be in (0, 1000]");
  if (!ffmpeg_on_path()) input_error(path_, "ffmpeg not found on PATH (scripts/setup.sh installs it)");
  check_output_directory(path_);
  temp_ = make_temp_beside(path_);
  log_ = make_temp_beside(temp_);
  temp_on_signal_ = std::make_unique<RemoveOnSignal>(temp_);
  log_on_signal_ = std::make_unique<RemoveOnSignal>(log_);
  // A dead ffmpeg must turn into an error from fwrite (EPIPE), not kill us with SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  char size[64], rate[32];
  std::snprintf(size, sizeof(size), "%ux%u", width, height);
  std::snprintf(rate, sizeof(rate), "%g", fps);
  const std::string command =
      std::string("ffmpeg -nostdin -hide_banner -loglevel error -y -f rawvideo -pix_fmt rgb24 -s ") + size + " -r " +
      rate + " -i - -vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p -f " + muxer(path_) + " " +
      shell_quote(temp_.string()) + " 2>" + shell_quote(log_.string());
  pipe_ = ::popen(command.c_str(), "w");
  if (!pipe_) input_error(path_, "cannot start ffmpeg: " + std::string(std::strerror(errno)));
}

VideoWriter::~VideoWriter() {
  if (pipe_) ::pclose(pipe_);
  std::error_code ec;
  std::filesystem::remove(log_, ec);
  std::filesystem::remove(temp_, ec);  // after finish() it is already renamed: nothing to remove
}

void VideoWriter::write(const Image& image, int, int step) {
  if (image.width != width_ || image.height != height_) throw std::logic_error("frame size changed during a video");
  const std::vector<uint8_t> rgb = to_rgb8(image, background_);
  if (std::fwrite(rgb.data(), 1, rgb.size(), pipe_) != rgb.size()) {
    ::pclose(pipe_);
    pipe_ = nullptr;
    const std::string said = last_line(log_);
    input_error(path_,
                "ffmpeg stopped taking frames at step " + std::to_string(step) + (said.empty() ? "" : ": " + said));
  }
  ++frames_;
}

void VideoWriter::finish() {
  if (!pipe_) return;
  const bool flushed = std::fflush(pipe_) == 0;
  const int status = ::pclose(pipe_);
  pipe_ = nullptr;
  const std::string said = last_line(log_);
  if (status == -1) input_error(path_, "ffmpeg: " + std::string(std::strerror(errno)));
  if (!flushed || !WIFEXITED(status) || WEXITSTATUS(status) != 0 || !said.empty())
    input_error(path_, "ffmpeg failed (exit status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                           ")" + (said.empty() ? "" : ": " + said));
  std::error_code ec;
  if (frames_ == 0 || std::filesystem::file_size(temp_, ec) == 0 || ec)
    input_error(path_, "ffmpeg wrote no video (" + std::to_string(frames_) + " frames given)");
  if (std::rename(temp_.c_str(), path_.c_str()) != 0)
    input_error(path_, "cannot rename the finished video into place: " + std::string(std::strerror(errno)));
}

// ---------------------------------------------------------------------------------------------
namespace {
// The CUDA renderer's value store: GPU buffers filled on their own stream.
class GpuValueStore : public ValueStore {
 public:
  GpuValueStore(int count, uint64_t floats_each) : buffers_(count, floats_each) {}
  const float* data(int buffer) const override { return buffers_.data(buffer); }
  void upload(int buffer, const float* staging, uint64_t floats) override { buffers_.upload(buffer, staging, floats); }
  uint64_t bytes() const override { return buffers_.bytes(); }
  const char* where() const override { return "GPU"; }

 private:
  cuda::DeviceValueBuffers buffers_;
};

FrameRequest stream_request(const RenderSetup& setup) {
  FrameRequest r;
  r.tf = setup.tf;
  r.camera = setup.camera;
  r.width = setup.settings.width;
  r.height = setup.settings.height;
  r.integrator = setup.settings.integrator;
  r.skip = setup.settings.skip;
  r.range_mode = setup.settings.brick_ranges ? RangeMode::per_brick : RangeMode::tight;
  return r;
}
}  // namespace

RendererStages::RendererStages(const Dataset& dataset, const RenderSetup& setup, FrameWriter* writer)
    : dataset_(dataset), request_(stream_request(setup)), writer_(writer), renderer_(dataset, setup.device) {
  // The BVH template is built once before the first frame (paper 000, section 5.6).
  renderer_.refit(request_, true);
}

RendererStages::~RendererStages() = default;

std::unique_ptr<ValueStore> RendererStages::make_value_store(int count, uint64_t bytes_each) {
  if (renderer_.device() != Device::cuda) return make_host_value_store(count, bytes_each);
  return std::make_unique<GpuValueStore>(count, dataset_.manifest().value_count());
}

void RendererStages::set_request(const FrameRequest& request) {
  if (request.second_field >= 0)
    throw UsageError(
        "a second field (colour field, blackbody temperature): not available when streaming (one field "
        "per step)");
  if (request.stored_ranges)
    throw UsageError("stored ranges: not available when streaming (the ranges stage computes them)");
  request_ = request;
}

void RendererStages::ranges(const FrameData& frame) {
  renderer_.use_values(frame.values);
  renderer_.compute_ranges(request_);
}

void RendererStages::refit(const FrameData&, bool rebuild) { renderer_.refit(request_, rebuild); }

void RendererStages::render(const FrameData&) { image_ = renderer_.render_image(request_); }

void RendererStages::output(const FrameData& frame) {
  if (writer_) writer_->write(image_, frame.frame, frame.step);
  if (on_image) on_image(frame, image_);
}

}  // namespace vs::stream
