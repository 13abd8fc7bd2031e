// Libraries opened at first use (io/shared_library.h): a function comes back callable, and a
// missing library or function is one InputError that names it and says what needs it.
#include "volstream/io/shared_library.h"

#include <gtest/gtest.h>

#include <cstring>

#include "volstream/core/error.h"

namespace vs {
namespace {

// The C library's soname on glibc, the platform volstream builds on.
constexpr const char* kLibc = "libc.so.6";

TEST(SharedLibrary, FunctionsComeBackCallable) {
  const SharedLibrary libc(kLibc, "this test needs it");
  const auto length = libc.function<decltype(&std::strlen)>("strlen");
  EXPECT_EQ(length("volstream"), 9u);
}

// The table that the Exodus and CGNS readers declare, here over two libc functions.
#define LIBC_FUNCTIONS(X) X(strlen) X(strcmp)
VOLSTREAM_LIBRARY_CALLS(LibcCalls, LIBC_FUNCTIONS);

TEST(SharedLibrary, CallTablesTakeEveryFunctionListed) {
  const SharedLibrary libc(kLibc, "this test needs it");
  const LibcCalls calls(libc);
  EXPECT_EQ(calls.strlen("abc"), 3u);
  EXPECT_LT(calls.strcmp("a", "b"), 0);
}

std::string error_of(const auto& attempt) {
  try {
    attempt();
  } catch (const InputError& e) {
    return e.file() + ": " + e.what();  // as the user sees it, after "volstream: "
  }
  return "no InputError";
}

TEST(SharedLibrary, AMissingLibraryIsOneLineNamingIt) {
  const std::string what =
      error_of([] { SharedLibrary("libvolstream_absent.so.7", "Widget files need it (apt-get install widgets)"); });
  EXPECT_NE(what.find("libvolstream_absent.so.7: cannot load it ("), std::string::npos) << what;
  EXPECT_NE(what.find("); Widget files need it (apt-get install widgets)"), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

TEST(SharedLibrary, AMissingFunctionIsOneLineNamingIt) {
  const SharedLibrary libc(kLibc, "Widget files need it");
  const std::string what = error_of([&] { libc.function<void (*)()>("volstream_no_such_function"); });
  EXPECT_NE(what.find("libc.so.6: has no function volstream_no_such_function ("), std::string::npos) << what;
  EXPECT_NE(what.find("Widget files need it"), std::string::npos) << what;
}

}  // namespace
}  // namespace vs
