#include "volstream/io/solver_files.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <new>
#include <stdexcept>
#include <utility>

#include "volstream/core/error.h"

namespace vs {

namespace {

// A variable named NAME_x, NAMEX, ... : NAME and the axis (0-2), or axis -1.
std::pair<std::string, int> vector_component(const std::string& name) {
  if (name.size() < 2) return {name, -1};
  const char axis = char(std::tolower(static_cast<unsigned char>(name.back())));
  if (axis < 'x' || axis > 'z') return {name, -1};
  std::string base = name.substr(0, name.size() - 1);
  if (base.size() > 1 && base.back() == '_') base.pop_back();
  return {base, axis - 'x'};
}

bool g_in_reading_child = false;
constexpr int kChildRefused = 3;  // the child's read threw; its message follows on the pipe

ssize_t read_retrying(int fd, char* buffer, size_t size) {
  ssize_t n;
  while ((n = ::read(fd, buffer, size)) < 0 && errno == EINTR) {
  }
  return n;
}

}  // namespace

std::vector<VariableGroup> group_vector_variables(const std::vector<std::string>& names) {
  std::vector<VariableGroup> out;
  for (size_t i = 0; i < names.size(); ++i) {
    const auto [base, axis] = vector_component(names[i]);
    if (axis == 0 && i + 2 < names.size() && vector_component(names[i + 1]) == std::pair(base, 1) &&
        vector_component(names[i + 2]) == std::pair(base, 2)) {
      out.push_back({base, int(i), 3});
      i += 2;
    } else {
      out.push_back({names[i].empty() ? "variable_" + std::to_string(i + 1) : names[i], int(i), 1});
    }
  }
  return out;
}

std::string trimmed_name(std::string s) {
  s.erase(std::find(s.begin(), s.end(), '\0'), s.end());
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  return s;
}

bool reading_in_child() { return g_in_reading_child; }

// Looked up through the library that brought HDF5 in: volstream neither links libhdf5 nor
// includes its header.
void skip_hdf5_exit_pass(const SharedLibrary& hdf5_user) {
  if (auto* dont_atexit = hdf5_user.function_if_any<int (*)()>("H5dont_atexit")) dont_atexit();
}

void read_in_child_first(const std::string& file, const std::string& format, const std::function<void()>& read) {
  if (g_in_reading_child) return;
  int channel[2];
  if (pipe(channel) != 0) return;  // no child to be had: read in place
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    close(channel[0]);
    close(channel[1]);
    return;
  }
  if (pid == 0) {
    close(channel[0]);
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, 2);
    g_in_reading_child = true;
    std::string error;
    try {
      read();
    } catch (const std::bad_alloc&) {
      error = "out of memory";
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (!error.empty() && write(channel[1], error.data(), error.size()) < 0) error = "unreadable";
    _exit(error.empty() ? 0 : kChildRefused);  // no exit handlers: the library's would run on a bad state
  }
  close(channel[1]);
  std::string error;
  char buffer[512];
  for (ssize_t n; (n = read_retrying(channel[0], buffer, sizeof buffer)) > 0;) error.append(buffer, size_t(n));
  close(channel[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  // The child's refusal is the file's; the parent never opens the file, so the library's state
  // stays clean (a failed open can leave HDF5 objects behind that it complains of at exit).
  if (WIFEXITED(status) && WEXITSTATUS(status) == kChildRefused && !error.empty()) input_error(file, error);
  input_error(file, "a damaged " + format + " file: the HDF5 library failed reading it (" +
                        (WIFSIGNALED(status) ? "signal " + std::to_string(WTERMSIG(status))
                                             : "exit status " + std::to_string(WEXITSTATUS(status))) +
                        ")");
}

}  // namespace vs
