// AMReX plotfiles (3D, cell-centred) as an AmrSource, and a writer for tests, fuzz seeds and
// benchmarks.
//
// A plotfile is a directory: `Header` (components, time, geometry, per-level grid counts),
// per level a VisMF header `Level_L/Cell_H` (the BoxArray and, per box, the data file and offset)
// and data files `Level_L/Cell_D_xxxxx` holding FABs: a text line
//   FAB ((8, (64 11 52 0 1 12 0 1023)),(8, (8 7 6 5 4 3 2 1)))((lo) (hi) (0,0,0)) ncomp
// followed by the values, component after component, x fastest within a component.
//
// Mapping to grid units: the finest level's cell is one grid unit; a level-l cell has width
// W_l = product of the ref ratios from l to the finest level, Cell.level = log2(W_l) and
// Cell.lower = (index - domain_lo_l) * W_l. Only leaf cells are produced (cells under a finer box
// are dropped), in input order: level by level, box by box, x fastest within a box.
#pragma once
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "volstream/amr/source.h"

namespace vs {

// True if dir looks like an AMReX plotfile: a directory with a "Header" file whose first line is a
// plotfile version string such as "HyperCLaw-V1.1". Never throws.
bool is_plotfile(const std::filesystem::path& dir);

// One plotfile, or a series of plotfile directories as time steps (same hierarchy and components in
// each, else InputError). Headers of all steps are checked here; FAB data is checked when read.
std::unique_ptr<AmrSource> open_plotfile_series(const std::vector<std::filesystem::path>& dirs);

// Writer: a 3D cell-centred plotfile in AMReX's layout.
struct PlotfileLevel {
  std::vector<box3i> boxes;  // inclusive index boxes [lower, upper] in this level's index space
};
struct PlotfileSpec {
  std::vector<std::string> components;
  vec3d prob_lo{0, 0, 0}, prob_hi{1, 1, 1};
  box3i level0_domain;          // inclusive index box of the coarsest level
  std::vector<int> ref_ratios;  // between level l and l+1 (powers of two)
  std::vector<PlotfileLevel> levels;
  bool float32 = false;  // FAB data as float32 instead of float64
  double time = 0;
  int boxes_per_fab_file = 2;  // several FABs per Cell_D_xxxxx file, at increasing offsets
  bool big_endian = false;     // FAB data byte order (AMReX on x86 writes little endian)
  int nghost = 0;              // ghost cells stored around each FAB (value() is asked for them too)
};
// value(component, level, i, j, k) -> value of that cell (index space of the level). The writer
// does not validate the spec, so tests can write inconsistent plotfiles on purpose.
void write_plotfile(const std::filesystem::path& dir, const PlotfileSpec& spec,
                    const std::function<double(int, int, int, int, int)>& value);

}  // namespace vs
