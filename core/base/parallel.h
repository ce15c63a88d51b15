// core/base/parallel.h: a TBB parallel_for over [begin, end) with the fork/join happens-before edges stated for
// ThreadSanitizer (core/base/tsan.h), for every parallel loop outside the renderer's own arena (the AOV feature pass,
// the NFOR denoiser): Debian's libtbb is not TSan-instrumented, so without them TSan reports the loop's tasks
// racing with the code before and after it.
#pragma once

#include <sched.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <thread>

#include "core/base/tsan.h"

namespace pv {

// The cores this thread may run on (its affinity mask, e.g. under taskset or a Slurm allocation), at least 1: what
// "as many threads as there are cores" means. std::thread::hardware_concurrency() counts every core of the machine,
// which under a smaller mask oversubscribes and reports threads that never ran.
inline int usable_cores() {
    cpu_set_t cpus;
    if (sched_getaffinity(0, sizeof cpus, &cpus) == 0) return std::max(1, CPU_COUNT(&cpus));
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

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
