#include "volstream/stream/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <future>
#include <numeric>

#include "volstream/backend/parallel.h"
#include "volstream/core/error.h"

namespace vs::stream {

namespace {
constexpr const char* kLevelNames[kLevelCount] = {"baseline",   "async-io", "pinned", "direct-io",
                                                  "preordered", "refit",    "overlap"};
}

const char* level_name(Level level) { return kLevelNames[int(level)]; }

bool parse_level(const std::string& name, Level& out) {
  for (int i = 0; i < kLevelCount; ++i)
    if (name == kLevelNames[i]) {
      out = Level(i);
      return true;
    }
  return false;
}

std::string level_names() {
  std::string s;
  for (const char* n : kLevelNames) {
    if (!s.empty()) s += '|';
    s += n;
  }
  return s;
}

PipelineFlags PipelineFlags::at(Level level) {
  const int l = int(level);
  PipelineFlags f;
  f.async_io = l >= int(Level::async_io);
  f.pinned = l >= int(Level::pinned);
  f.direct_io = l >= int(Level::direct_io);
  f.preordered = l >= int(Level::preordered);
  f.refit = l >= int(Level::refit);
  f.overlap = l >= int(Level::overlap);
  return f;
}

// Where one step's values travel: file buffer -(flatten)-> staging -(upload)-> device. Without
// flattening the file buffer is the staging buffer. Two slots alternate when a background loader
// fills one while the frame thread uses the other.
struct Pipeline::Slot {
  float* file = nullptr;
  float* staging = nullptr;
  int device = 0;  // buffer in device_values_
  int step = -1;
  Phase done = Phase::none;
};

Pipeline::Pipeline(const Dataset& dataset, int field, PipelineFlags flags, FrameStages& stages, Timeline* timeline)
    : dataset_(dataset),
      field_(field),
      flags_(flags),
      stages_(stages),
      timeline_(timeline),
      reader_(dataset.manifest().value_count(), flags.direct_io ? ReadMode::direct : ReadMode::buffered) {
  if (flags_.overlap) flags_.async_io = true;  // the overlapped upload runs on the loader thread
  const int slots = flags_.async_io ? 2 : 1;
  // A buffer that the loader writes while the frame thread may still use the other one needs two
  // copies; one the frame thread alone writes needs one.
  const int staging_copies = (flags_.preordered || flags_.overlap) ? slots : 1;
  const int device_copies = flags_.overlap ? 2 : 1;
  auto allocate = [&](int count, bool pinned) {
    std::vector<HostBuffer> v;
    for (int i = 0; i < count; ++i) v.emplace_back(reader_.padded_bytes(), pinned);
    return v;
  };
  if (!flags_.preordered) file_buffers_ = allocate(slots, false);
  staging_buffers_ = allocate(staging_copies, flags_.pinned);
  device_values_ = stages_.make_value_store(device_copies, reader_.padded_bytes());
  if (!flags_.preordered) {
    file_order_ = dataset.has_file_order();
    if (file_order_) {
      flatten_index_ = dataset.load_file_index();  // checked to be a permutation
    } else {
      flatten_index_.resize(dataset.manifest().value_count());
      std::iota(flatten_index_.begin(), flatten_index_.end(), 0u);
    }
  }
  for (int k = 0; k < slots; ++k) {
    auto slot = std::make_unique<Slot>();
    slot->staging = staging_buffers_[size_t(k % staging_copies)].floats();
    slot->file = flags_.preordered ? slot->staging : file_buffers_[size_t(k)].floats();
    slot->device = k % device_copies;
    slots_.push_back(std::move(slot));
  }
}

Pipeline::~Pipeline() = default;

Pipeline::Slot& Pipeline::slot_for(uint64_t frame) { return *slots_[size_t(frame % slots_.size())]; }

uint64_t Pipeline::buffer_bytes() const {
  uint64_t total = flatten_index_.size() * sizeof(uint32_t) + device_values_->bytes();
  for (const auto* list : {&file_buffers_, &staging_buffers_})
    for (const HostBuffer& b : *list) total += b.bytes();
  return total;
}

std::string Pipeline::describe_buffers() const {
  char text[256];
  // Page-locking can succeed for the first buffer and fail for the next (RLIMIT_MEMLOCK).
  HostBuffer::Pinning weakest = staging_buffers_.front().pinning();
  for (const HostBuffer& b : staging_buffers_) weakest = std::min(weakest, b.pinning());
  const char* pinning = pinning_name(weakest);
  std::snprintf(text, sizeof(text), "%zu file + %zu staging (%s) + %zu device (%s) buffers: %.1f MiB",
                file_buffers_.size(), staging_buffers_.size(), pinning, size_t(flags_.overlap ? 2 : 1),
                device_values_->where(), double(buffer_bytes()) / (1 << 20));
  return text;
}

bool Pipeline::direct_io_active() const { return reader_.direct(); }

const char* Pipeline::flatten_mode() const {
  if (flags_.preordered) return "none";
  return file_order_ ? "file-order" : "identity";
}

std::string Pipeline::pin_failure() const {
  for (const HostBuffer& b : staging_buffers_)
    if (!b.pin_failure().empty()) return b.pin_failure();
  return {};
}

// ---------------------------------------------------------------------------------------------
namespace {
class HostValueStore : public ValueStore {
 public:
  HostValueStore(int count, uint64_t bytes_each) {
    for (int i = 0; i < count; ++i) buffers_.emplace_back(bytes_each, false, "field values");
  }
  const float* data(int buffer) const override { return buffers_.at(size_t(buffer)).floats(); }
  void upload(int buffer, const float* staging, uint64_t floats) override {
    std::memcpy(buffers_.at(size_t(buffer)).floats(), staging, floats * sizeof(float));
  }
  uint64_t bytes() const override { return buffers_.size() * buffers_.front().bytes(); }
  const char* where() const override { return "host"; }

 private:
  std::vector<HostBuffer> buffers_;
};
}  // namespace

std::unique_ptr<ValueStore> make_host_value_store(int count, uint64_t bytes_each) {
  return std::make_unique<HostValueStore>(count, bytes_each);
}

// ---------------------------------------------------------------------------------------------
// Advances `slot` (already assigned its step) through the phases up to `upto`, skipping what is
// done; the loader thread and the frame thread share this one code path.
void Pipeline::load(Slot& slot, int step, Phase upto, int lane) {
  if (slot.done < Phase::read) {
    Timeline::Scope s(timeline_, Stage::read, step, lane);
    // The file-order copy (when there is one) is what a flattening level reads; the reader's
    // missing / truncated / wrong-size errors name that file and the step.
    reader_.read(file_order_ ? dataset_.file_order_values_path(field_, step) : dataset_.values_path(field_, step), step,
                 slot.file);
    slot.done = Phase::read;
  }
  if (upto >= Phase::uploaded && slot.done < Phase::uploaded) {
    Timeline::Scope s(timeline_, Stage::upload, step, lane);
    if (!flags_.preordered) flatten(slot);
    device_values_->upload(slot.device, slot.staging, dataset_.manifest().value_count());
    slot.done = Phase::uploaded;
  }
}

// The baseline's per-frame reorder from file order to device order (see pipeline.h): a gather
// through the dataset's file index, or through the identity without file-order copies.
void Pipeline::flatten(const Slot& slot) {
  const uint32_t* index = flatten_index_.data();
  const float* in = slot.file;
  float* out = slot.staging;
  parallel_for_ranges(
      int64_t(flatten_index_.size()),
      [&](int64_t begin, int64_t end) {
        for (int64_t i = begin; i < end; ++i) out[i] = in[index[i]];
      },
      1 << 16);
}

void Pipeline::process(Slot& slot, int frame) {
  const int step = slot.step;
  const FrameData f{frame, step, device_values_->data(slot.device)};
  {
    Timeline::Scope s(timeline_, Stage::ranges, step, kFrameLane);
    stages_.ranges(f);
  }
  {
    Timeline::Scope s(timeline_, Stage::refit, step, kFrameLane);
    stages_.refit(f, !flags_.refit);
  }
  {
    Timeline::Scope s(timeline_, Stage::render, step, kFrameLane);
    stages_.render(f);
  }
  Timeline::Scope s(timeline_, Stage::output, step, kFrameLane);
  stages_.output(f);
}

PlayStats Pipeline::play(const std::vector<int>& steps, const std::function<void(int, int)>& on_frame) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const uint64_t bytes_before = reader_.bytes_read();
  const int frames = int(steps.size());
  for (int i = 0; i < frames; ++i) {
    const int step = steps[size_t(i)];
    advance(i, step, i + 1 < frames ? steps[size_t(i) + 1] : -1);
    if (on_frame) on_frame(i, step);
  }
  PlayStats stats;
  stats.frames = frames;
  stats.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  stats.bytes_read = reader_.bytes_read() - bytes_before;
  return stats;
}

void Pipeline::advance(int frame, int step, int next) {
  Slot& slot = slot_for(advances_++);
  take_prefetched(slot, step);
  // Start the next step on the loader before touching this one (paper 000, Fig. 4).
  if (flags_.async_io && next >= 0) {
    Slot& ahead = slot_for(advances_);
    ahead.step = next;
    ahead.done = Phase::none;
    const Phase upto = flags_.overlap ? Phase::uploaded : Phase::read;
    loader_ = std::async(std::launch::async, [this, &ahead, upto] { load(ahead, ahead.step, upto, kPrefetchLane); });
  }
  load(slot, step, Phase::uploaded, kFrameLane);  // whatever the loader did not do
  process(slot, frame);
}

// Waits for the loader's work on `slot`; keeps it if it is `step`, else starts `slot` afresh
// (the buffers it shares with the other slot may hold another step by now).
void Pipeline::take_prefetched(Slot& slot, int step) {
  bool prefetched = false;
  if (loader_.valid()) {
    std::future<void> loading = std::move(loader_);
    try {
      loading.get();
      prefetched = slot.step == step;
    } catch (...) {
      if (slot.step == step) throw;  // the loader's error for this step (it names the file)
    }
  }
  if (prefetched) return;
  slot.step = step;
  slot.done = Phase::none;
}

}  // namespace vs::stream
