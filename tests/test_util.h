#pragma once
// Helpers shared by the test programs.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include "shvol/core/error.h"

namespace shvol::test {

/// The message of the shvol::Error that f throws, or "(no error)".
inline std::string messageOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

/// The bytes of a file ("" if it cannot be read).
inline std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A path in the test temporary directory that only the running test uses ("shvol_", its suite
/// and name, then `name`): ctest runs tests in parallel, each in its own process, and two tests
/// writing the same file while the other reads it fail at random.
inline std::string privateTempPath(const std::string& name) {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string id = info ? std::string(info->test_suite_name()) + "." + info->name() : "none";
    for (char& c : id)
        if (c == '/') c = '_';  // parameterized tests: Cases/Suite.Name/3
    return ::testing::TempDir() + "/shvol_" + id + "_" + name;
}

}  // namespace shvol::test
