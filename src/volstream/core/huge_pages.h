// Transparent huge pages for large fresh allocations.
#pragma once
#include <cstdint>

namespace vs {

// Asks the kernel to back the 2 MiB-aligned part of a fresh allocation with transparent huge
// pages (Linux's "madvise" mode): a mesh's load fills 80 MB of arrays, and one page fault per
// 2 MiB instead of per 4 KiB takes much of the load's kernel time off. Advice only: where it is
// refused or unknown, nothing changes. Call it before the memory is first touched.
void prefer_huge_pages(void* data, uint64_t bytes);

}  // namespace vs
