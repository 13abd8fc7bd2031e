#include "volstream/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stdio.h>  // renameat2

#include <cerrno>
#include <cstring>

#include "volstream/core/error.h"

namespace vs {
namespace fs = std::filesystem;

namespace {
fs::path parent_or_dot(const fs::path& p) { return p.has_parent_path() ? p.parent_path() : fs::path("."); }

// ".<name>.part-XXXXXX" beside the target: the template mkstemp and mkdtemp fill in.
std::string temp_template(const fs::path& target) {
  std::string file = ".";  // appended, not "." + ...: GCC 12 warns falsely (-Wrestrict) on that
  file += target.filename().string();
  file += ".part-XXXXXX";
  return (parent_or_dot(target) / file).string();
}

// Creates the temporary file; returns its descriptor (InputError naming the target otherwise).
int create_temp(const fs::path& target, fs::path& temp) {
  std::string name = temp_template(target);
  const int fd = ::mkstemp(name.data());  // O_EXCL: a planted file or link makes it pick another name
  if (fd < 0) input_error(target.string(), std::string("cannot create: ") + std::strerror(errno));
  ::fchmod(fd, 0644);  // mkstemp makes 0600; outputs are meant to be shared like any other file
  temp = name;
  return fd;
}
}  // namespace

fs::path make_temp_beside(const fs::path& target) {
  fs::path temp;
  ::close(create_temp(target, temp));
  return temp;
}

namespace {
void check_parent_writable(const fs::path& output) {
  const fs::path dir = parent_or_dot(output);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) input_error(output.string(), "output directory " + dir.string() + " does not exist");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    input_error(output.string(), "output directory " + dir.string() + " is not writable");
}
}  // namespace

void check_output_directory(const fs::path& output) {
  check_parent_writable(output);
  if (std::error_code ec; fs::is_directory(output, ec)) input_error(output.string(), "is a directory");
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  if (std::error_code ec; fs::is_directory(target_, ec)) input_error(target_.string(), "is a directory");
  const int fd = create_temp(target_, temp_);
  on_signal_ = std::make_unique<RemoveOnSignal>(temp_);
  file_ = ::fdopen(fd, "wb");
  if (!file_) {
    ::close(fd);
    fail("cannot open for writing", errno);
  }
}

AtomicFile::~AtomicFile() {
  if (file_) std::fclose(file_);
  if (!committed_) ::unlink(temp_.c_str());
}

void AtomicFile::fail(const std::string& what, int error) {
  if (file_) std::fclose(file_);
  file_ = nullptr;
  ::unlink(temp_.c_str());
  committed_ = true;  // nothing left to remove
  input_error(target_.string(), what + (error ? std::string(": ") + std::strerror(error) : std::string()));
}

void AtomicFile::write(const void* data, uint64_t bytes) {
  if (bytes && std::fwrite(data, 1, bytes, file_) != bytes) fail("write failed", errno);
}

void AtomicFile::commit() {
  if (std::fflush(file_) != 0 || std::ferror(file_)) fail("write failed", errno);
  if (::fsync(::fileno(file_)) != 0 && errno != EINVAL) fail("write failed (fsync)", errno);
  FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) fail("write failed (close)", errno);
  if (std::rename(temp_.c_str(), target_.c_str()) != 0) fail("cannot rename the finished file into place", errno);
  committed_ = true;
}

StagedDirectory::StagedDirectory(fs::path target, const std::string& marker) : target_(std::move(target)) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(target_, ec);
  if (st.type() == fs::file_type::symlink)
    input_error(target_.string(), "is a symbolic link; give the directory itself");
  if (st.type() != fs::file_type::not_found) {
    if (st.type() != fs::file_type::directory) input_error(target_.string(), "exists and is not a directory");
    if (!fs::is_empty(target_, ec) && !fs::exists(target_ / marker, ec))
      input_error(target_.string(), "is a non-empty directory without " + marker + "; refusing to replace it");
  }
  check_parent_writable(target_);
  std::string name = temp_template(target_);
  if (!::mkdtemp(name.data()))
    input_error(target_.string(), std::string("cannot create a directory beside it: ") + std::strerror(errno));
  temp_ = name;
  on_signal_ = std::make_unique<RemoveOnSignal>(temp_);
  ::chmod(temp_.c_str(), 0755);  // mkdtemp makes 0700; a dataset is meant to be shared
}

StagedDirectory::~StagedDirectory() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(temp_, ec);
}

void StagedDirectory::commit() {
  std::error_code ec;
  const bool replace = fs::exists(fs::symlink_status(target_, ec));
  // RENAME_EXCHANGE swaps the two names in one step: readers see the old or the new dataset.
  if (replace ? ::renameat2(AT_FDCWD, temp_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) != 0
              : std::rename(temp_.c_str(), target_.c_str()) != 0)
    input_error(target_.string(),
                std::string("cannot move the finished directory into place: ") + std::strerror(errno));
  committed_ = true;
  if (replace) fs::remove_all(temp_, ec);  // now the old contents
}

void write_file_atomic(const fs::path& path, const void* data, uint64_t bytes, uint64_t pad_to) {
  AtomicFile out(path);
  out.write(data, bytes);
  static const char zeros[4096] = {};
  for (uint64_t left = (bytes + pad_to - 1) / pad_to * pad_to - bytes; left > 0;) {
    const uint64_t chunk = left < sizeof(zeros) ? left : sizeof(zeros);
    out.write(zeros, chunk);
    left -= chunk;
  }
  out.commit();
}

}  // namespace vs
