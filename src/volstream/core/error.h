// Errors that reach the user as one line "volstream: <file>: <what>" and exit status 2.
#pragma once
#include <stdexcept>
#include <string>

namespace vs {

// Bad or inconsistent input: a file that is missing, truncated, garbage or contradicts itself.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, const std::string& what) : std::runtime_error(what), file_(std::move(file)) {}
  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

// A bad command-line value (no file involved).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] inline void input_error(const std::string& file, const std::string& what) { throw InputError(file, what); }
inline void input_check(bool ok, const std::string& file, const std::string& what) {
  if (!ok) throw InputError(file, what);
}
// For a literal message: no string is made unless the check fails (checks run in loops over
// millions of records).
inline void input_check(bool ok, const std::string& file, const char* what) {
  if (!ok) throw InputError(file, what);
}

}  // namespace vs
