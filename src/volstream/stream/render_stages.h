// The pipeline's refit, render and output stages done by the AMR renderer (render/renderer.h),
// and the frame writers behind the output stage: a PNG sequence or a video through ffmpeg.
#pragma once
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "volstream/frame/frame_renderer.h"
#include "volstream/io/cleanup.h"
#include "volstream/io/dataset.h"
#include "volstream/io/image.h"
#include "volstream/stream/pipeline.h"

namespace vs::stream {

// Receives each finished frame (the output stage).
class FrameWriter {
 public:
  virtual ~FrameWriter() = default;
  virtual void write(const Image& image, int frame, int step) = 0;
  virtual void finish() {}  // flush and check (e.g. the encoder's exit status)
};

// Writes `pattern` with the frame index substituted for its one %d (e.g. frames_%04d.png). Each
// file is written under a temporary name and renamed, so an interrupted run leaves no partial frame.
class PngSequenceWriter : public FrameWriter {
 public:
  PngSequenceWriter(std::string pattern, vec3f background);  // UsageError for a bad pattern
  void write(const Image& image, int frame, int step) override;
  static std::string format(const std::string& pattern, int frame);

 private:
  std::string pattern_;
  vec3f background_;
};

// Pipes rgb24 frames into `ffmpeg ... -c:v libx264 -pix_fmt yuv420p` (odd sizes are padded to
// even ones, as yuv420p needs), writing a temporary beside OUT. finish() closes the pipe, checks
// ffmpeg's exit status, its messages and the frame count, and only then renames the video to
// OUT; otherwise (or when destroyed before finish) the temporary is removed.
class VideoWriter : public FrameWriter {
 public:
  VideoWriter(std::string path, uint32_t width, uint32_t height, double fps, vec3f background);
  ~VideoWriter() override;
  void write(const Image& image, int frame, int step) override;
  void finish() override;

 private:
  std::string path_;
  uint32_t width_, height_;
  vec3f background_;
  FILE* pipe_ = nullptr;
  std::filesystem::path temp_, log_;  // ffmpeg's output and messages until finish() (atomic_file.h)
  std::unique_ptr<RemoveOnSignal> temp_on_signal_, log_on_signal_;
  int frames_ = 0;
};

// True for outputs that go to ffmpeg (.mp4, .mkv, .mov).
bool is_video_path(const std::string& path);

// What to render: all fixed for the whole animation (the transfer function's range too).
struct RenderSetup {
  TransferFunctionSpec tf;
  FrameSettings settings;
  Camera camera;
  Device device = Device::cpu;
};

// The stages through the library's FrameRenderer (frame/frame_renderer.h): ranges: per-ABR
// value ranges of the values the pipeline read (and uploaded); refit: classify the ABRs from
// them and refit the BVH template; a rebuild builds the BVH from scratch first (what the levels
// before `refit` pay every frame); render: one image; output: hands it to the writer (if any).
// On CUDA the values live in GPU memory and ranges, classification, refit and render run there;
// only the BVH build and the image cross the bus.
class RendererStages : public FrameStages {
 public:
  RendererStages(const Dataset& dataset, const RenderSetup& setup, FrameWriter* writer);
  ~RendererStages() override;
  std::unique_ptr<ValueStore> make_value_store(int count, uint64_t bytes_each) override;
  void ranges(const FrameData& frame) override;
  void refit(const FrameData& frame, bool rebuild) override;
  void render(const FrameData& frame) override;
  void output(const FrameData& frame) override;
  // What the next frames show, for a caller that changes the view between frames (the viewer's
  // play): anything but the field, which is the pipeline's, and the step, which is the frame's.
  // UsageError for what the pipeline cannot stream: a second field (colour field, blackbody
  // temperature) or stored ranges.
  void set_request(const FrameRequest& request);
  const Image& image() const { return image_; }
  uint64_t visible_abrs() const { return renderer_.visible_regions(); }
  // Called after each frame's output with its image (tests and benchmarks compare frames).
  std::function<void(const FrameData&, const Image&)> on_image;

 private:
  const Dataset& dataset_;
  FrameRequest request_;
  FrameWriter* writer_;
  FrameRenderer renderer_;
  Image image_;
};

}  // namespace vs::stream
