#include "volstream/io/cleanup.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace vs {
namespace {
constexpr int kSlots = 32;
constexpr size_t kPathMax = 4096;

// A slot is free (0), being written (1) or holds a path (2); the handler reads only state 2.
struct Slot {
  std::atomic<int> state{0};
  char path[kPathMax];
};
Slot g_slots[kSlots];

// Removes everything under the open directory `dir` (closed here): getdents64 and unlinkat,
// which are plain system calls, unlike opendir or std::filesystem.
void remove_children(int dir, int depth) {
  alignas(8) char buf[4096];
  // Other threads may still be writing: stop after a pass that removed nothing.
  for (bool removed = true; removed;) {
    removed = false;
    const long n = ::syscall(SYS_getdents64, dir, buf, sizeof buf);
    if (n <= 0) break;
    for (long off = 0; off < n;) {
      struct Entry {
        uint64_t ino;
        int64_t off;
        unsigned short reclen;
        unsigned char type;
        char name[1];
      };
      const Entry* e = reinterpret_cast<const Entry*>(buf + off);
      off += e->reclen;
      if (!std::strcmp(e->name, ".") || !std::strcmp(e->name, "..")) continue;
      if (::unlinkat(dir, e->name, 0) == 0) {
        removed = true;
        continue;
      }
      if (depth > 16) continue;
      const int sub = ::openat(dir, e->name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
      if (sub < 0) continue;
      remove_children(sub, depth + 1);
      removed |= ::unlinkat(dir, e->name, AT_REMOVEDIR) == 0;
    }
    ::lseek(dir, 0, SEEK_SET);  // entries were removed: read the (shorter) directory again
  }
  ::close(dir);
}

void remove_path(const char* path) {
  if (::unlink(path) == 0) return;
  const int dir = ::open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (dir < 0) return;
  remove_children(dir, 0);
  ::rmdir(path);
}

extern "C" void on_signal(int sig) {
  for (Slot& s : g_slots)
    if (s.state.load() == 2) remove_path(s.path);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void install_handlers() {
  static const bool installed = [] {
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction sa {};
      sa.sa_handler = on_signal;
      sigemptyset(&sa.sa_mask);
      struct sigaction old {};
      ::sigaction(sig, nullptr, &old);
      if (old.sa_handler == SIG_IGN) continue;  // e.g. started with nohup: keep ignoring
      ::sigaction(sig, &sa, nullptr);
    }
    return true;
  }();
  (void)installed;
}
}  // namespace

RemoveOnSignal::RemoveOnSignal(const std::filesystem::path& path) {
  const std::string abs = std::filesystem::absolute(path).string();
  if (abs.size() >= kPathMax) return;
  install_handlers();
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!g_slots[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(g_slots[i].path, abs.c_str(), abs.size() + 1);
    g_slots[i].state.store(2);
    slot_ = i;
    return;
  }
}

RemoveOnSignal::~RemoveOnSignal() {
  if (slot_ >= 0) g_slots[slot_].state.store(0);
}

}  // namespace vs
