#include "volstream/io/solver_files.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
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

bool reading_in_child() { return g_in_reading_child; }

void read_in_child_first(const std::string& file, const std::string& format, const std::function<void()>& read) {
  if (g_in_reading_child) return;
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return;  // no child to be had: read in place
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) dup2(null, 2);
    g_in_reading_child = true;
    try {
      read();
    } catch (...) {
    }
    _exit(0);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  input_error(file, "a damaged " + format + " file: the HDF5 library failed reading it (" +
                        (WIFSIGNALED(status) ? "signal " + std::to_string(WTERMSIG(status))
                                             : "exit status " + std::to_string(WEXITSTATUS(status))) +
                        ")");
}

}  // namespace vs
