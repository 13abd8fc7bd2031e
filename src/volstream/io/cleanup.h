// Temporary outputs removed when the process is ended by SIGINT, SIGTERM or SIGHUP. Their owners
// remove them on every normal path (success or exception); this covers Ctrl-C during a long run.
#pragma once
#include <filesystem>

namespace vs {

// Registers `path` (a file or a directory tree) while alive; the handler removes what is
// registered with async-signal-safe calls only, then ends the process as the signal would have.
class RemoveOnSignal {
 public:
  explicit RemoveOnSignal(const std::filesystem::path& path);
  ~RemoveOnSignal();
  RemoveOnSignal(const RemoveOnSignal&) = delete;
  RemoveOnSignal& operator=(const RemoveOnSignal&) = delete;

 private:
  int slot_ = -1;  // -1: every slot taken (then only the normal paths clean up)
};

}  // namespace vs
