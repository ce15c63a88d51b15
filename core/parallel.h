// core/parallel.h: a TBB parallel_for over [begin, end) with the fork/join happens-before edges stated for
// ThreadSanitizer (core/tsan.h), for every parallel loop outside the renderer's own arena (the AOV feature pass,
// the NFOR denoiser): Debian's libtbb is not TSan-instrumented, so without them TSan reports the loop's tasks
// racing with the code before and after it.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/tsan.h"

namespace pv {

template <class Fn>
void parallel_for_range(int begin, int end, Fn&& fn) {
    const char fork_edge = 0, join_edge = 0;  // addresses for TSan's happens-before edges
    tsan_release(&fork_edge);
    tbb::parallel_for(tbb::blocked_range<int>(begin, end), [&](const tbb::blocked_range<int>& range) {
        const TsanTaskScope tsan_scope(&fork_edge, &join_edge);
        fn(range);
    });
    tsan_acquire(&join_edge);
}

}  // namespace pv
