// core/base/huge_pages.h: memory for data the path tracer reads at random (texels, packed hit records) on 2 MiB pages
// where Linux grants them. A hit touches a texel block and a record scattered over megabytes: on 4 KiB pages most
// such reads miss the DTLB and wait for a page walk (docs/ray-speed.md).
#pragma once

#include <cstddef>
#include <memory>

namespace pv {

constexpr size_t kHugePageBytes = size_t(2) << 20;
// Below this many bytes a region is a plain 64-byte aligned allocation: a huge page would waste more than half of
// itself, and so little data rarely costs page walks (the Cornell box).
constexpr size_t kHugePageMinBytes = size_t(1) << 20;

// A region of at least `bytes` bytes, 64-byte aligned; from kHugePageMinBytes up, 2 MiB aligned,
// rounded up to a whole number of 2 MiB pages (less than 2 MiB more; the tail is not touched) and advised for huge
// pages (Linux; ignored where the kernel refuses). Its first `bytes` bytes are zero. Freed when the last copy of the
// pointer goes. Throws std::bad_alloc when out of memory. Transparent huge pages are "madvise" by default on Debian,
// hence the alignment and MADV_HUGEPAGE. The kernel may still back the region with 4 KiB pages (THP "never", no free
// huge page): the data and results are the same.
std::shared_ptr<std::byte> allocate_region(size_t bytes);

// The size allocate_region(bytes) reserves: bytes rounded up to 64, or to 2 MiB from kHugePageMinBytes up.
size_t region_capacity(size_t bytes);

// Returns the heap's free memory to the kernel (glibc's malloc_trim; nothing elsewhere): after data has moved into a
// region, its old storage would otherwise stay resident in the heap.
void return_freed_heap_memory();

}  // namespace pv
