#pragma once
// Locating the real recorded data of ../shared/data for tests.

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <gtest/gtest.h>

namespace fieldlidar::test {

/// The real-data folder: $FIELDLIDAR_DATA_DIR, else the folder configured in CMake.
inline std::filesystem::path data_dir() {
  if (const char* env = std::getenv("FIELDLIDAR_DATA_DIR"); env && *env) return env;
#ifdef FIELDLIDAR_TEST_DATA_DIR
  return FIELDLIDAR_TEST_DATA_DIR;
#else
  return std::filesystem::path("..") / "shared" / "data";
#endif
}

inline std::filesystem::path data_file(const std::string& relative) {
  return data_dir() / relative;
}

/// The temporary folders this test process made; removed when it ends if every test passed,
/// kept (and named on stderr) after a failure or with $FIELDLIDAR_KEEP_TEST_DIRS set.
class TempDirs {
 public:
  static TempDirs& instance() {
    static TempDirs dirs;
    return dirs;
  }
  void add(const std::filesystem::path& dir) { dirs_.push_back(dir); }
  TempDirs(const TempDirs&) = delete;
  TempDirs& operator=(const TempDirs&) = delete;
  ~TempDirs() {
    const char* keep = std::getenv("FIELDLIDAR_KEEP_TEST_DIRS");
    const bool passed = ::testing::UnitTest::GetInstance()->Passed();
    for (const auto& dir : dirs_) {
      if (passed && !(keep && *keep)) {
        std::error_code ignored;
        std::filesystem::remove_all(dir, ignored);
      } else {
        std::fprintf(stderr, "kept test folder %s\n", dir.c_str());
      }
    }
  }

 private:
  TempDirs() = default;
  std::vector<std::filesystem::path> dirs_;
};

/// A fresh empty temporary folder for one test (see TempDirs for when it is removed).
inline std::filesystem::path temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() /
             ("fieldlidar_test_" + name + "_" +
              std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  TempDirs::instance().add(dir);
  return dir;
}

}  // namespace fieldlidar::test

/// Skips the current test, saying which file is missing, when real data is not there.
#define FIELDLIDAR_REQUIRE_DATA(relative)                                               \
  do {                                                                                  \
    if (!std::filesystem::exists(::fieldlidar::test::data_file(relative)))              \
      GTEST_SKIP() << "real data file " << ::fieldlidar::test::data_file(relative)      \
                   << " is absent (set FIELDLIDAR_DATA_DIR to the shared/data folder)"; \
  } while (0)
