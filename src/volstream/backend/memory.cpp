#include "volstream/backend/memory.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>

namespace vs {

const char* to_string(MemorySpace space) {
  switch (space) {
    case MemorySpace::host:
      return "host";
    case MemorySpace::pinned:
      return "pinned host";
    case MemorySpace::device:
      return "device";
  }
  return "?";
}

namespace {
struct LedgerState {
  std::mutex mutex;
  std::map<std::string, MemoryEntry> entries;
};
LedgerState& state() {
  static LedgerState s;
  return s;
}
}  // namespace

void MemoryLedger::add(const std::string& structure, MemorySpace space, int64_t bytes) {
  if (bytes == 0) return;
  LedgerState& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  MemoryEntry& e = s.entries[structure];
  e.structure = structure;
  const int i = int(space);
  e.bytes[i] += bytes;
  e.peak[i] = std::max(e.peak[i], e.bytes[i]);
}

std::vector<MemoryEntry> MemoryLedger::snapshot() const {
  LedgerState& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  std::vector<MemoryEntry> out;
  for (const auto& [name, e] : s.entries) out.push_back(e);
  return out;
}

int64_t MemoryLedger::total(MemorySpace space) const {
  int64_t sum = 0;
  for (const MemoryEntry& e : snapshot()) sum += e.bytes[int(space)];
  return sum;
}

MemoryLedger& memory_ledger() {
  static MemoryLedger ledger;
  return ledger;
}

std::string format_memory(const std::vector<MemoryEntry>& entries) {
  std::string out;
  for (MemorySpace space : {MemorySpace::host, MemorySpace::pinned, MemorySpace::device}) {
    const int i = int(space);
    int64_t total = 0;
    std::string parts;
    for (const MemoryEntry& e : entries) {
      if (e.bytes[i] <= 0) continue;
      total += e.bytes[i];
      char part[160];
      std::snprintf(part, sizeof(part), "%s%s %.1f", parts.empty() ? "" : ", ", e.structure.c_str(),
                    e.bytes[i] / 1048576.0);
      parts += part;
    }
    if (total == 0) continue;
    char line[96];
    std::snprintf(line, sizeof(line), "%s %.1f MiB (", to_string(space), total / 1048576.0);
    out += (out.empty() ? "" : "; ") + std::string(line) + parts + ")";
  }
  return out.empty() ? "nothing counted" : out;
}

CountedBytes::CountedBytes(std::string structure, MemorySpace space, int64_t bytes)
    : structure_(std::move(structure)), space_(space) {
  set(bytes);
}

CountedBytes::CountedBytes(CountedBytes&& o) noexcept
    : structure_(std::move(o.structure_)), space_(o.space_), bytes_(o.bytes_) {
  o.bytes_ = 0;
}

CountedBytes& CountedBytes::operator=(CountedBytes&& o) noexcept {
  if (this != &o) {
    set(0);
    structure_ = std::move(o.structure_);
    space_ = o.space_;
    bytes_ = o.bytes_;
    o.bytes_ = 0;
  }
  return *this;
}

CountedBytes::~CountedBytes() { set(0); }

void CountedBytes::set(int64_t bytes) {
  if (bytes == bytes_) return;
  memory_ledger().add(structure_, space_, bytes - bytes_);
  bytes_ = bytes;
}

double peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // KiB on Linux
}

}  // namespace vs
