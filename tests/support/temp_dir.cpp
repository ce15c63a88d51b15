// tests/support/temp_dir.cpp: see temp_dir.h.
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>

namespace pv::test {

namespace fs = std::filesystem;

TestDir::TestDir(const std::string& prefix) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path = fs::temp_directory_path() /
           (prefix + "_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    fs::remove_all(path);
    fs::create_directories(path);
}

TestDir::~TestDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
}

std::string TestDir::write(const std::string& name, const std::string& bytes) const {
    std::ofstream(path / name, std::ios::binary) << bytes;
    return file(name);
}

bool TestDir::holds_only(const std::vector<std::string>& names) const {
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(path)) {
        ++n;
        if (std::find(names.begin(), names.end(), e.path().filename().string()) == names.end()) return false;
    }
    return n == names.size();
}

}  // namespace pv::test
