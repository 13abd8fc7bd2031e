// Errors that reach the user as one line "volstream: <file>: <what>" and exit status 2.
#pragma once
#include <exception>
#include <new>
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

// An error as the user sees it: the line after "volstream: " and the exit status (2 for bad
// input or usage and out of memory, 1 for anything unforeseen).
struct ErrorReport {
  std::string line;
  int status = 2;
};
inline ErrorReport describe_error(std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const InputError& e) {
    return {e.file() + ": " + e.what(), 2};
  } catch (const UsageError& e) {
    return {e.what(), 2};
  } catch (const std::bad_alloc&) {
    return {"out of memory", 2};
  } catch (const std::exception& e) {
    return {e.what(), 1};
  } catch (...) {
    return {"unknown error", 1};
  }
}

// An error every data-parallel rank agreed on (mpi/comm.h): rank 0 prints it, all exit with it.
class AgreedError : public std::runtime_error {
 public:
  explicit AgreedError(const ErrorReport& r) : std::runtime_error(r.line), report_(r) {}
  const ErrorReport& report() const { return report_; }

 private:
  ErrorReport report_;
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
