// core/base/huge_pages.cpp: 2 MiB-aligned regions advised MADV_HUGEPAGE (see huge_pages.h).
#include "core/base/huge_pages.h"

#include <cstdlib>
#include <cstring>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pv {

size_t region_capacity(size_t bytes) {
    const size_t align = bytes >= kHugePageMinBytes ? kHugePageBytes : size_t(64);
    return (bytes + align - 1) / align * align;
}

std::shared_ptr<std::byte> allocate_region(size_t bytes) {
    const size_t capacity = region_capacity(bytes == 0 ? 1 : bytes);
    // From the size asked for, not the capacity: just below the threshold, 64-byte rounding can reach it.
    const bool huge = bytes >= kHugePageMinBytes;
    // aligned_alloc needs the size to be a multiple of the alignment: capacity is.
    void* p = std::aligned_alloc(huge ? kHugePageBytes : size_t(64), capacity);
    if (!p) throw std::bad_alloc();
#if defined(MADV_HUGEPAGE)
    // Advised before the first touch, so the page faults below can already allocate huge pages. A failure (EINVAL:
    // a kernel without THP) leaves plain pages: nothing to report.
    if (huge) (void)madvise(p, capacity, MADV_HUGEPAGE);
#endif
    // Zeroed up to `bytes` only: the tail of the last page stays untouched (no memory behind it on 4 KiB pages).
    std::memset(p, 0, bytes);
    return std::shared_ptr<std::byte>(static_cast<std::byte*>(p), [](std::byte* q) { std::free(q); });
}

void return_freed_heap_memory() {
#if defined(__GLIBC__)
    (void)malloc_trim(0);
#endif
}

}  // namespace pv
