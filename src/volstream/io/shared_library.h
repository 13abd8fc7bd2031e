// A C library that a reader opens when it first needs it (dlopen), not when volstream starts.
//
// libnetcdf (Exodus II) and libcgns (CGNS) bring in HDF5, curl, gnutls, Kerberos and ICU: linked
// into the executable they took about 20 ms of every command's start (a bare `volstream` 33.5 ms
// against 13.5 ms without them, bench/RESULTS.md), a tenth of a 1M-tet render's whole command,
// although only those two formats use them. The readers call them through a table of function pointers that
// VOLSTREAM_LIBRARY_CALLS declares, filled from the library the first time a file needs it.
#pragma once
#include <string>

namespace vs {

class SharedLibrary {
 public:
  // Opens `soname` (the build's library, as CMake found it); InputError if it does not load.
  // `needed_for` ends that error and a missing function's: what needs the library and how to
  // install it ("Exodus II files need it (Debian: apt-get install libnetcdf-dev)").
  SharedLibrary(std::string soname, std::string needed_for);
  // The library stays loaded to the end of the process: it may have registered exit handlers
  // (HDF5 does), which need its code.
  ~SharedLibrary() = default;
  SharedLibrary(const SharedLibrary&) = delete;
  SharedLibrary& operator=(const SharedLibrary&) = delete;

  // The function `name` as a pointer of type F; InputError if the library lacks it.
  template <class F>
  F function(const char* name) const {
    return reinterpret_cast<F>(symbol(name));
  }
  // The same, null where neither the library nor one it brought in has it.
  template <class F>
  F function_if_any(const char* name) const {
    return reinterpret_cast<F>(dlsym_of(name));
  }

 private:
  void* symbol(const char* name) const;
  void* dlsym_of(const char* name) const;
  void* handle_ = nullptr;
  std::string soname_, needed_for_;
};

}  // namespace vs

// Declares `struct Name` with one member per C function that LIST names (LIST(X) expands X(f)
// for each f), of the type of its declaration in the library's header, and a constructor that
// takes each from a SharedLibrary. Call sites read `netcdf().nc_open(...)` (io/exodus.cpp).
#define VOLSTREAM_LIBRARY_MEMBER(f) decltype(&::f) f = nullptr;
#define VOLSTREAM_LIBRARY_RESOLVE(f) f = library.function<decltype(&::f)>(#f);
// clang-format off
#define VOLSTREAM_LIBRARY_CALLS(Name, LIST)                                                \
  struct Name {                                                                            \
    explicit Name(const ::vs::SharedLibrary& library) { LIST(VOLSTREAM_LIBRARY_RESOLVE) }  \
    LIST(VOLSTREAM_LIBRARY_MEMBER)                                                         \
  }
// clang-format on
