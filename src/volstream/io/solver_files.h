// What the readers of finite-element and CFD solvers' files (Exodus II: io/exodus.h; CGNS:
// io/cgns.h) share: their node orders turned into VTK's, their scalar variables grouped into
// vectors, and reading through an HDF5 library in a child process first.
#pragma once
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "volstream/io/shared_library.h"

namespace vs {

// For each VTK node, the file's node (0-based) that is it, for orders both formats use:
// - a wedge whose first triangle faces its second (VTK's faces away): the triangles' second and
//   third nodes change places;
// - a quadratic hexahedron and wedge whose mid-edge nodes come bottom, vertical, top (VTK: bottom,
//   top, vertical), the wedge also turned as above.
inline constexpr std::array<int, 6> kWedgeFacingInward = {0, 2, 1, 3, 5, 4};
inline constexpr std::array<int, 20> kHex20BottomVerticalTop = {0,  1,  2,  3,  4,  5,  6,  7,  8,  9,
                                                                10, 11, 16, 17, 18, 19, 12, 13, 14, 15};
inline constexpr std::array<int, 15> kWedge15FacingInwardBottomVerticalTop = {0, 2,  1,  3,  5, 4,  8, 7,
                                                                              6, 14, 13, 12, 9, 11, 10};

// A name as these files store it, in a fixed-width field: up to its first NUL, without trailing
// blanks.
std::string trimmed_name(std::string s);

// Solvers write a vector as three scalar variables NAME_x, NAME_y, NAME_z (Exodus) or NAMEX,
// NAMEY, NAMEZ (CGNS's VelocityX ...). A group is one array of the file's variables: `first`
// (0-based) and `components` (1, or 3 for such a triple, named NAME).
struct VariableGroup {
  std::string name;
  int first = 0, components = 1;
};
// Unnamed variables are called "variable_<i>" (1-based).
std::vector<VariableGroup> group_vector_variables(const std::vector<std::string>& names);

// HDF5 (1.10) reads some damaged files unsafely (fuzzing found it freeing an uninitialised
// pointer while opening one), and a failed open can leave its objects behind, which it complains
// of on stderr at exit. So `read` (every read the real one will make) runs in a child process
// first, its stderr silenced, ended without exit handlers. An exception there becomes the
// parent's InputError naming `file`, with the child's message, before the parent opens the file
// at all; a child that dies, InputError "a damaged FORMAT file: the HDF5 library failed reading it
// (signal 11)". Inside the child (reading_in_child() true) it runs nothing.
// The library must be loaded before (hdf5_reader_calls), so that the child inherits it and it is
// loaded once.
void read_in_child_first(const std::string& file, const std::string& format, const std::function<void()>& read);
bool reading_in_child();

// HDF5 closes itself at exit and, when a damaged file left one of its objects open, prints
// "HDF5: infinite loop closing library" and a line of object codes after volstream's one-line
// error. volstream only reads HDF5 files, so there is nothing to flush: the reader of a library
// that reads through HDF5 turns that exit pass off as it loads the library (HDF5 came in with it).
void skip_hdf5_exit_pass(const SharedLibrary& hdf5_user);

// The call table (VOLSTREAM_LIBRARY_CALLS) of a library that reads through HDF5, libnetcdf or
// libcgns: loaded at the first call, once, with HDF5's exit pass off.
template <class Calls>
const Calls& hdf5_reader_calls(const char* soname, const char* needed_for) {
  static const SharedLibrary library(soname, needed_for);
  static const Calls calls(library);
  static const bool exit_pass_off = (skip_hdf5_exit_pass(library), true);
  (void)exit_pass_off;
  return calls;
}

}  // namespace vs
