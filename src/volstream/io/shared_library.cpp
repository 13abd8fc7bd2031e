#include "volstream/io/shared_library.h"

#include <dlfcn.h>

#include "volstream/core/error.h"

namespace vs {

namespace {

std::string last_dl_error() {
  const char* what = dlerror();
  return what ? what : "no reason given";
}

}  // namespace

SharedLibrary::SharedLibrary(std::string soname, std::string needed_for)
    : soname_(std::move(soname)), needed_for_(std::move(needed_for)) {
  // RTLD_NOW: a library that cannot resolve its own symbols fails here, with dlerror's reason,
  // rather than at some later call. RTLD_LOCAL: its symbols stay out of the global scope.
  handle_ = dlopen(soname_.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle_) input_error(soname_, "cannot load it (" + last_dl_error() + "); " + needed_for_);
}

// Through the handle, the lookup searches the library and the libraries it brought in (HDF5
// under libcgns), which RTLD_LOCAL keeps out of RTLD_DEFAULT's reach.
void* SharedLibrary::dlsym_of(const char* name) const { return dlsym(handle_, name); }

void* SharedLibrary::symbol(const char* name) const {
  dlerror();  // clears an earlier error, so that the check below sees this lookup's
  void* address = dlsym_of(name);
  if (!address)
    input_error(soname_, std::string("has no function ") + name + " (" + last_dl_error() + "); " + needed_for_);
  return address;
}

}  // namespace vs
