// tests/base/test_usable_cores.cpp: "as many threads as cores" (threads = 0) means the cores this process may run on,
// not every core of the machine: under taskset or a Slurm allocation the renderer must not oversubscribe nor report
// threads that never ran.
// Test kinds: unit
#include <gtest/gtest.h>
#include <sched.h>

#include "core/base/parallel.h"
#include "core/frame/renderer.h"
#include "support/scenes.h"

namespace pv {
namespace {

// Restricts the calling thread to its first allowed core for the scope (affinity is per thread: the test
// runner's other threads are untouched), and restores the mask after.
class OneCore {
public:
    OneCore() {
        ok_ = sched_getaffinity(0, sizeof saved_, &saved_) == 0;
        if (!ok_) return;
        cpu_set_t one;
        CPU_ZERO(&one);
        for (int c = 0; c < CPU_SETSIZE; ++c)
            if (CPU_ISSET(c, &saved_)) {
                CPU_SET(c, &one);
                break;
            }
        ok_ = sched_setaffinity(0, sizeof one, &one) == 0;
    }
    ~OneCore() {
        if (ok_) sched_setaffinity(0, sizeof saved_, &saved_);
    }
    bool ok() const { return ok_; }

private:
    cpu_set_t saved_;
    bool ok_ = false;
};

TEST(UsableCores, FollowTheAffinityMask) {
    cpu_set_t mask;
    ASSERT_EQ(sched_getaffinity(0, sizeof mask, &mask), 0);
    EXPECT_EQ(usable_cores(), CPU_COUNT(&mask));
    OneCore one;
    ASSERT_TRUE(one.ok());
    EXPECT_EQ(usable_cores(), 1);
}

TEST(UsableCores, RendererWithZeroThreadsUsesTheCoresItMayRunOn) {
    OneCore one;
    ASSERT_TRUE(one.ok());
    Renderer r(test::cornell_box(), 0);
    EXPECT_EQ(r.threads(), 1);  // hardware_concurrency() would say every core of the machine
}

}  // namespace
}  // namespace pv
