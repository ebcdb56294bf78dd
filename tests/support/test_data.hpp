#pragma once
// Locating the real recorded data of ../shared/data for tests.

#include <cstdlib>
#include <filesystem>
#include <string>

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

/// A fresh empty temporary folder for one test.
inline std::filesystem::path temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() /
             ("fieldlidar_test_" + name + "_" +
              std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
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
