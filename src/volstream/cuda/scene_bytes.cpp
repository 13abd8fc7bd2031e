#include "volstream/cuda/scene_bytes.h"

#include <vector>

#include "volstream/accel/bvh.h"
#include "volstream/accel/refit.h"
#include "volstream/amr/ranges.h"

namespace vs::cuda {

std::map<std::string, uint64_t> device_scene_bytes(const AmrTopology& t, int fields, uint32_t width, uint32_t height) {
  const uint64_t abrs = t.abrs.size();
  const uint64_t nodes = abrs ? 2 * abrs - 1 : 0;  // binary BVH, one ABR per leaf
  const uint64_t macrocells = macrocell_offsets(t.bricks).back();
  const uint64_t pixels = uint64_t(width) * height;
  std::map<std::string, uint64_t> b;
  b["bricks"] = t.bricks.size() * sizeof(Brick);
  b["ABRs"] = abrs * sizeof(Abr);
  b["ABR brick lists"] = t.abr_bricks.size() * sizeof(uint32_t);
  b["BVH"] = nodes * sizeof(BvhNode);
  b["BVH (refit)"] = nodes * sizeof(BvhNode) + nodes * sizeof(uint32_t);  // refit copy + schedule
  b["ABR ranges"] = (t.bricks.size() + 1) * sizeof(uint64_t) + macrocells * sizeof(Range) + abrs * sizeof(Range) +
                    abrs * sizeof(uint8_t) + sizeof(unsigned long long);
  b["field values"] = uint64_t(fields) * t.cell_count * sizeof(float);
  b["image"] = pixels * (4 * sizeof(float) + sizeof(uint32_t));
  return b;
}

}  // namespace vs::cuda
