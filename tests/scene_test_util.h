// Helpers shared by the scene-loading tests: a fresh temporary directory per test, file
// writing, and capturing the InputError message of a load that must fail.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "scene/load.h"

namespace penumbra::test {

// A directory named after the running test under this build's test output folder (not the
// system temp folder, which two builds testing at the same time would share), emptied first.
inline std::filesystem::path freshTempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "-" + info->name();
    for (char& c : name)
        if (c == '/') c = '_';
    auto dir = std::filesystem::path(PENUMBRA_TEST_OUTPUT) / "scenes" / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

inline std::filesystem::path writeFile(const std::filesystem::path& file, const std::string& bytes) {
    std::ofstream(file, std::ios::binary) << bytes;
    return file;
}

// The message of the InputError that loading `file` throws; fails the test (and returns "")
// when nothing or something else is thrown. Messages must be one line.
inline std::string loadError(const std::filesystem::path& file, const std::vector<Override>& overrides = {}) {
    try {
        loadScene(file, overrides);
    } catch (const InputError& e) {
        std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << "multi-line message: " << message;
        return message;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
        return "";
    }
    ADD_FAILURE() << "expected InputError loading " << file;
    return "";
}

}  // namespace penumbra::test
