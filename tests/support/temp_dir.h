// tests/support/temp_dir.h: a fresh folder for the running test (named after the test, the process and a prefix),
// removed when the test ends; the file tests and CLI tests write their inputs and outputs there.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace pv::test {

struct TestDir {
    std::filesystem::path path;
    // <temp>/<prefix>_<pid>_<suite>_<test>, emptied first.
    explicit TestDir(const std::string& prefix);
    ~TestDir();
    TestDir(const TestDir&) = delete;
    TestDir& operator=(const TestDir&) = delete;

    std::string file(const std::string& name) const { return (path / name).string(); }
    // The same path quoted for the shell (run_command passes its arguments as written).
    std::string operator/(const std::string& name) const { return "'" + file(name) + "'"; }
    // Writes `bytes` to `name` and returns its path.
    std::string write(const std::string& name, const std::string& bytes) const;
    // The folder holds exactly these files.
    bool holds_only(const std::vector<std::string>& names) const;
};

}  // namespace pv::test
