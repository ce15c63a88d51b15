// tests/support/child.h: runs a piece of a test in a forked child, so that a crash, a hang or a runaway allocation
// of the code under test (a loader fed a damaged file) is observed instead of ending the test process.
#pragma once

#include <functional>

namespace pv::test {

struct ChildResult {
    bool finished = false;  // false: killed at the deadline (the old code's hang)
    int exit_code = -1;     // fn's return value; 128 + the signal for a crash; 98 for an exception
    long max_rss_kb = 0;    // the child's peak resident memory
};

// Deadline of every bounded run: a hang (the fault under test), never slowness. Long enough for a sanitizer build
// on a loaded machine (issue 26): no test asserts that work ends within a shorter interval.
constexpr int kDeadlineSeconds = 300;

// Runs `fn` in a forked child (its return value is the exit code), killed after `seconds`.
ChildResult run_bounded(const std::function<int()>& fn, double seconds = kDeadlineSeconds);

}  // namespace pv::test
