// The per-frame streaming pipeline of paper 000, section 5 (Fig. 3): for each time step
//   read -> upload -> ranges -> refit -> render -> output
// with every optimisation of the paper as a flag, and the paper's steps as cumulative levels:
//
//   baseline    synchronous; buffered reads; CPU "flattening" pass; BVH rebuilt every frame (5.1)
//   async-io    the next step is read on a background thread while this one is processed (5.2)
//   pinned      page-locked staging buffers (5.3)
//   direct-io   O_DIRECT reads that bypass the page cache (5.4)
//   preordered  values are read straight into staging in device order: no flattening (5.5)
//   refit       the template BVH is refit instead of rebuilt (5.6)
//   overlap     the upload of the next step runs on the loader, into the second device buffer,
//               while this step renders (5.7)
//
// The flattening of the baseline (ExaBricks reorders every frame from file order to device
// order): levels before `preordered` read into a separate file buffer and gather it into staging,
// staging[i] = file[file_index[i]]. A dataset converted with `--file-order` holds every step in
// file (source) order too, plus the permutation file_index.bin; those levels read that copy and
// gather through the real, scattered index, so the frames are the same as from the device-order
// files. A dataset without it (the default: it doubles the values on disk) has only device-order
// files; then the index is the identity, which costs the extra buffer and the index + value +
// store traffic of a gather but not the cache misses of a scattered one, i.e. it under-states the
// flattening (flatten_is_identity() says so). From `preordered` on, the device-order files are
// read straight into staging.
//
// Where the values go is the renderer's choice (FrameStages::make_value_store): host memory for
// the CPU renderer (the upload is a copy), GPU memory for the CUDA one (the upload is a DMA copy
// on its own stream, from page-locked staging at the `pinned` level, and at `overlap` the
// loader thread uploads step t+S into the second device buffer while step t renders).
// Memory is a fixed number of buffers, whatever the number of steps.
#pragma once
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "volstream/amr/model.h"
#include "volstream/io/dataset.h"
#include "volstream/stream/step_reader.h"
#include "volstream/stream/timeline.h"

namespace vs::stream {

enum class Level : uint8_t { baseline, async_io, pinned, direct_io, preordered, refit, overlap };
inline constexpr int kLevelCount = 7;
const char* level_name(Level level);                    // "baseline", "async-io", ...
bool parse_level(const std::string& name, Level& out);  // false if unknown
std::string level_names();                              // "baseline|async-io|...", for help texts

struct PipelineFlags {
  bool async_io = false;    // prefetch the next step on a background thread
  bool pinned = false;      // page-locked staging
  bool direct_io = false;   // O_DIRECT reads
  bool preordered = false;  // no CPU flattening pass
  bool refit = false;       // refit the template BVH instead of rebuilding
  bool overlap = false;     // upload the next step on the loader, into a second device buffer (implies async_io)
  static PipelineFlags at(Level level);  // every optimisation up to and including `level`
};

// One frame as the stages see it.
struct FrameData {
  int frame = 0;                  // position in the played sequence
  int step = 0;                   // time step
  const float* values = nullptr;  // in the value store (host or GPU memory): cell_count floats, device order
};

// The buffers the renderer reads a step's values from.
class ValueStore {
 public:
  virtual ~ValueStore() = default;
  virtual const float* data(int buffer) const = 0;
  // Copies `floats` values from staging into `buffer`; returns when done. May run on another
  // thread than the renderer's stages (the overlap level's loader).
  virtual void upload(int buffer, const float* staging, uint64_t floats) = 0;
  virtual uint64_t bytes() const = 0;
  virtual const char* where() const = 0;  // "host" or "GPU", for reports
};

// `count` page-aligned buffers in host memory: the CPU renderer's "device".
std::unique_ptr<ValueStore> make_host_value_store(int count, uint64_t bytes_each);

// What the renderer provides: called on the frame thread, in this order, once per frame.
class FrameStages {
 public:
  virtual ~FrameStages() = default;
  // Where the pipeline keeps the values of `count` steps at once (called once, up front).
  virtual std::unique_ptr<ValueStore> make_value_store(int count, uint64_t bytes_each) {
    return make_host_value_store(count, bytes_each);
  }
  // "ranges": per-ABR value ranges of the frame's values, where the values are.
  virtual void ranges(const FrameData& frame) = 0;
  // "refit": bring the acceleration structure up to date with the frame's ABR ranges; `rebuild`
  // asks for a BVH built from scratch (the levels before `refit`).
  virtual void refit(const FrameData& frame, bool rebuild) = 0;
  virtual void render(const FrameData& frame) = 0;
  virtual void output(const FrameData& frame) = 0;
};

struct PlayStats {
  int frames = 0;
  double seconds = 0;  // wall time from the first read to the last output
  uint64_t bytes_read = 0;
};

class Pipeline {
 public:
  // Allocates every buffer up front (see buffer_bytes()). `timeline` may be null.
  Pipeline(const Dataset& dataset, int field, PipelineFlags flags, FrameStages& stages, Timeline* timeline);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // Plays the steps in the given order, one frame each; the step after the current one in the
  // list is prefetched (so a jump costs one load). Throws InputError naming the step's file when
  // a step cannot be read; every frame before it has been output, that one and later ones not.
  // `on_frame` runs after each frame's output (progress bars).
  PlayStats play(const std::vector<int>& steps, const std::function<void(int frame, int step)>& on_frame = {});

  // One frame, for a caller that chooses each step as it goes (the viewer's play, whose camera
  // and transfer function change between frames through the stages): processes `step` as frame
  // `frame`, then returns while the loader (async levels) keeps loading `next` (-1: nothing).
  // A step that is not the `next` of the previous call is loaded here (a seek): what the loader
  // did is dropped, and so is its error. play() is a loop over this.
  void advance(int frame, int step, int next);

  const PipelineFlags& flags() const { return flags_; }
  uint64_t buffer_bytes() const;  // all per-step buffers together
  std::string describe_buffers()
      const;                      // e.g. "0 file + 2 staging (page-locked (cuda)) + 2 device (GPU) buffers: 16.0 MiB"
  bool direct_io_active() const;  // false if O_DIRECT fell back to buffered reads
  // The flatten pass of the levels before `preordered` (see above): "file-order" (the dataset's
  // file-order copies through the real index), "identity" (no such copies: device-order files
  // through the identity index), or "none" (from `preordered` on).
  const char* flatten_mode() const;
  // True when this level flattens but the dataset has no file-order copies, so the gather runs
  // through the identity and under-states the cost of a real reorder.
  bool flatten_is_identity() const { return !flags_.preordered && !file_order_; }
  // Why page-locking failed (empty if it worked or was not asked for).
  std::string pin_failure() const;

 private:
  struct Slot;
  enum class Phase : uint8_t { none, read, uploaded };
  void load(Slot& slot, int step, Phase upto, int lane);
  void flatten(const Slot& slot);
  void process(Slot& slot, int frame);
  void take_prefetched(Slot& slot, int step);
  Slot& slot_for(uint64_t frame);

  const Dataset& dataset_;
  int field_;
  PipelineFlags flags_;
  FrameStages& stages_;
  Timeline* timeline_;
  StepReader reader_;
  std::vector<HostBuffer> file_buffers_, staging_buffers_;
  std::unique_ptr<ValueStore> device_values_;
  std::vector<uint32_t> flatten_index_;  // file position of each device position (see above)
  bool file_order_ = false;              // reading the file-order copies (flatten_index_ is real)
  std::vector<std::unique_ptr<Slot>> slots_;
  uint64_t advances_ = 0;     // advance() calls so far: which slot is next
  std::future<void> loader_;  // the loader's work on the next slot; last, so it is waited for first
};

}  // namespace vs::stream
