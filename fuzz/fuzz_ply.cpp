// libFuzzer target: the PLY reader must return a cloud or throw fieldlidar::Error. It takes a
// path (PCL's PLYReader reads files), so each input is written to a temporary file first.
#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("fieldlidar_fuzz_" + std::to_string(::getpid()) + ".ply");
  static const bool cleanup = [] {
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove(path, ec);
    });
    return true;
  }();
  (void)cleanup;
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    if (size > 0) std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    return 0;
  }
  try {
    const auto cloud = fieldlidar::io::read_ply(path);
    (void)cloud.valid_count();
  } catch (const fieldlidar::Error&) {
  }
  return 0;
}
