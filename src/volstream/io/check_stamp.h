// A check of a dataset's files that passed, remembered until one of the files changes.
//
// Loading a mesh checks every element, BVH node, neighbour row and walk record against the rest,
// so that a damaged or hostile dataset is one line and exit 2, never a crash or a hang. On a
// mesh of 1 M tets that is about 60 ms of a 0.27 s render, paid again by every command that
// opens the same files (bench/RESULTS.md). A stamp, written after the check passed, holds the
// identity of every file the check read: device, inode, size, and the modification and
// status-change times. The kernel sets the status-change time (ctime) on every write, truncation,
// rename or metadata change, and no call sets it back, so a file changed after the check no
// longer matches its stamp and is checked again. The stamp also names the volstream library
// that checked (the same five fields of the file holding this code): a rebuilt volstream, whose
// checks may differ, trusts no stamp of another build.
//
// A load looks at the files after it has mapped them, so a file replaced before its mapping does
// not match the stamp of the one it replaced. A file changed in place while a command has it
// mapped was never covered by the checks either (the pages change under the mapping).
//
// Timestamps come from a coarse clock (a few ms; a second on some filesystems), so a file
// changed in the same tick as the check read it could keep its stamp: files changed less than
// kSettleSeconds before the check are not stamped (as git treats "racily clean" index entries).
//
// A stamp's file name hashes the check, the build and the files' paths, its content is compared
// whole. Stamps live in $VOLSTREAM_CHECK_STAMPS, else $XDG_CACHE_HOME/volstream/check_stamps, else
// $HOME/.cache/volstream/check_stamps (made mode 0700); VOLSTREAM_CHECK_STAMPS=off turns them
// off. A stamp is trusted only when it is a regular file of this user that nobody else may
// write. Writing one is best effort: a read-only or full cache only means checking again.
// Writing one also removes the stamps not written for 30 days (old builds, datasets long gone).
#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace vs {

inline constexpr double kSettleSeconds = 2.0;

class CheckStamp {
 public:
  // The stamp of check `what` (its name, e.g. "reference mesh") over `files`, as they are now.
  CheckStamp(std::string_view what, const std::vector<std::filesystem::path>& files);
  // True when the check passed on exactly these files before (and stamps are on).
  bool passed_before() const;
  // After the check passed: remembers it, unless a file had changed within kSettleSeconds.
  void record() const;
  // Where the stamp is kept (empty: stamps are off, or a file could not be looked at).
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::string identity_;  // what a stamp must hold, byte for byte
  bool settled_ = false;  // every file unchanged for kSettleSeconds
};

// The directory stamps are kept in; empty when they are off or no home is known.
std::filesystem::path check_stamp_directory();

}  // namespace vs
