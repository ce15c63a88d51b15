// tests/support/cli.h: runs a built program through the shell and captures its exit code, stdout and stderr
// (for the CLI tests: one-line errors, exit codes, files written or not).
#pragma once

#include <string>

namespace pv::test {

struct RunResult {
    int exit_code = -1;
    std::string out, err;
};

// Runs `'binary' args` (args are passed to the shell as written: quote paths) and collects its output.
RunResult run_command(const std::string& binary, const std::string& args);

// Number of '\n' in s.
size_t line_count(const std::string& s);

}  // namespace pv::test
