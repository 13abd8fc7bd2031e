// AmrSource: what every importer (AMReX plotfile, ExaBrick files, raw grids, the procedural
// demos) provides to the converter: the leaf cells once, and each field's values per step in the
// same order as the cells ("input order").
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "volstream/amr/model.h"

namespace vs {

struct WorldTransform {
  vec3d origin{0, 0, 0};     // world position of grid point (0,0,0)
  vec3d cell_size{1, 1, 1};  // world size of one grid unit (the finest cell width) per axis
  vec3d to_world(const vec3d& g) const { return origin + g * cell_size; }
  vec3d to_grid(const vec3d& w) const { return (w - origin) / cell_size; }
};

class AmrSource {
 public:
  virtual ~AmrSource() = default;
  // Leaf cells, each exactly once (no overlaps), in input order. May be moved out by the caller
  // (take_cells) to save memory; after that only read_values is used.
  virtual std::vector<Cell> take_cells() = 0;
  virtual uint64_t cell_count() const = 0;
  virtual WorldTransform transform() const = 0;
  virtual std::vector<std::string> field_names() const = 0;
  virtual int step_count() const = 0;
  virtual double step_time(int step) const { return double(step); }
  // Values of one field at one step in input order; out has cell_count() entries.
  // Throws InputError on bad data.
  virtual void read_values(int field, int step, float* out) = 0;
  // A short description for `info` ("AMReX plotfile", "demo jet", ...).
  virtual std::string description() const = 0;
  // The file named in errors about the cells (e.g. overlapping cells); defaults to description().
  virtual std::string origin() const { return description(); }
};

}  // namespace vs
