#include "volstream/io/check_stamp.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <sstream>

#include "volstream/core/error.h"
#include "volstream/io/atomic_file.h"

namespace vs {
namespace fs = std::filesystem;

namespace {

constexpr int kStampFormat = 1;
constexpr uint64_t kMaxStampBytes = 1u << 20;
constexpr int kStaleDays = 30;

int64_t nanoseconds(const timespec& t) { return int64_t(t.tv_sec) * 1000000000 + int64_t(t.tv_nsec); }

// Appends "dev ino size mtime ctime" of `path` (links followed) and raises `latest_change`;
// false when the file cannot be looked at.
bool describe(const fs::path& path, std::string& out, int64_t& latest_change) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) return false;
  const int64_t modified = nanoseconds(s.st_mtim), changed = nanoseconds(s.st_ctim);
  out += std::to_string(uint64_t(s.st_dev)) + ' ' + std::to_string(uint64_t(s.st_ino)) + ' ' +
         std::to_string(uint64_t(s.st_size)) + ' ' + std::to_string(modified) + ' ' + std::to_string(changed);
  latest_change = std::max({latest_change, modified, changed});
  return true;
}

// The file mapped at this code's address (the volstream binary, or the library the Python module
// links), from /proc/self/maps: dladdr names the main program by argv[0], which may be relative.
fs::path find_file_holding_this_code() {
  const auto here = reinterpret_cast<uintptr_t>(&check_stamp_directory);
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    std::istringstream fields(line);
    std::string span, perms, offset, dev, inode, path;
    uintptr_t begin = 0, end = 0;
    char dash = 0;
    if (!(fields >> span >> perms >> offset >> dev >> inode >> path)) continue;
    std::istringstream bounds(span);
    if (!(bounds >> std::hex >> begin >> dash >> end) || here < begin || here >= end) continue;
    return path.starts_with("/") ? fs::path(path) : fs::path();
  }
  return {};
}

// Looked up once per process: a command makes a stamp for its mesh and one for its walk records.
const fs::path& file_holding_this_code() {
  static const fs::path path = find_file_holding_this_code();
  return path;
}

int64_t now_nanoseconds() {
  timespec t{};
  clock_gettime(CLOCK_REALTIME, &t);
  return nanoseconds(t);
}

// The stamp's bytes if it is a regular file of this user that nobody else may write; else empty.
std::string read_trusted(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return {};
  std::string text;
  struct stat s {};
  if (::fstat(fd, &s) == 0 && S_ISREG(s.st_mode) && s.st_uid == ::geteuid() && (s.st_mode & 022) == 0 &&
      uint64_t(s.st_size) <= kMaxStampBytes) {
    text.resize(size_t(s.st_size));
    if (::read(fd, text.data(), text.size()) != ssize_t(text.size())) text.clear();
  }
  ::close(fd);
  return text;
}

// Removes the stamps in `dir` not written for kStaleDays (those of old builds and of datasets
// long gone), so that the cache does not grow with every build; a stamp still wanted is only
// checked and written again.
void remove_stale_stamps(const fs::path& dir) {
  const auto stale_before = fs::file_time_type::clock::now() - std::chrono::hours(24 * kStaleDays);
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    std::error_code entry_ec;
    if (entry.is_regular_file(entry_ec) && entry.last_write_time(entry_ec) < stale_before && !entry_ec)
      fs::remove(entry.path(), entry_ec);
  }
}

}  // namespace

fs::path check_stamp_directory() {
  if (const char* dir = std::getenv("VOLSTREAM_CHECK_STAMPS"); dir && *dir)
    return std::string_view(dir) == "off" ? fs::path() : fs::path(dir);
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache && *cache == '/')
    return fs::path(cache) / "volstream" / "check_stamps";
  if (const char* home = std::getenv("HOME"); home && *home == '/')
    return fs::path(home) / ".cache" / "volstream" / "check_stamps";
  return {};
}

CheckStamp::CheckStamp(std::string_view what, const std::vector<fs::path>& files) {
  const fs::path dir = check_stamp_directory();
  if (dir.empty()) return;
  const int64_t now = now_nanoseconds();
  int64_t latest_change = INT64_MIN, library_change = INT64_MIN;
  std::string identity = "volstream check stamp " + std::to_string(kStampFormat) + "\ncheck " + std::string(what);
  identity += "\nlibrary ";
  const fs::path& library = file_holding_this_code();
  if (library.empty() || !describe(library, identity, library_change)) return;
  // Named by the build as well as the check and the files: two builds used in turn (a benchmark's
  // base and new) keep a stamp each instead of replacing each other's.
  std::string names = identity;
  for (const fs::path& file : files) {
    std::error_code ec;
    const fs::path absolute = fs::absolute(file, ec).lexically_normal();
    if (ec) return;
    identity += "\nfile ";
    if (!describe(absolute, identity, latest_change)) return;
    identity += ' ' + absolute.string();
    names += '\n' + absolute.string();
  }
  identity += '\n';
  char name[32];
  // Only this build reads its stamps (the name holds its identity), so the standard library's
  // hash, stable within a build, names them.
  std::snprintf(name, sizeof(name), "%016llx", static_cast<unsigned long long>(std::hash<std::string>{}(names)));
  path_ = dir / name;
  identity_ = std::move(identity);
  settled_ = latest_change <= now - int64_t(kSettleSeconds * 1e9);
}

bool CheckStamp::passed_before() const { return !path_.empty() && read_trusted(path_) == identity_; }

void CheckStamp::record() const {
  if (path_.empty() || !settled_) return;
  const fs::path dir = path_.parent_path();
  std::error_code ec;
  if (fs::create_directories(dir, ec)) ::chmod(dir.c_str(), 0700);
  if (ec) return;
  try {
    write_file_atomic(path_, identity_.data(), identity_.size());  // a temporary renamed over the stamp
  } catch (const InputError&) {
    return;  // a read-only or full cache: the next command checks again
  }
  remove_stale_stamps(dir);
}

}  // namespace vs
