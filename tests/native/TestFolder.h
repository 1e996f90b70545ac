#pragma once
// A fresh folder for the files of one test, under the system's temporary folder, named after the
// test and the process so parallel runs do not meet; removed with the test's fixture.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace mwb::fixtures {

class TestFolder {
public:
    explicit TestFolder(const std::string& prefix)
        : dir_(std::filesystem::temp_directory_path() /
               (prefix + "_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name())) {
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    ~TestFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(dir_, ignored);
    }
    TestFolder(const TestFolder&) = delete;
    TestFolder& operator=(const TestFolder&) = delete;

    std::string path(const std::string& name) const { return (dir_ / name).string(); }

private:
    std::filesystem::path dir_;
};

}  // namespace mwb::fixtures
