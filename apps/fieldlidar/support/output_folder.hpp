#pragma once
/// \file An output folder made for a run: created up front (so that its files can be checked for
/// writing before the work), and removed again when the run ends without writing into it (bad
/// input refused after the check), so a refused command leaves no empty folder behind.

#include <filesystem>
#include <system_error>
#include <utility>

namespace fieldlidar::app {

class OutputFolder {
 public:
  explicit OutputFolder(std::filesystem::path dir)
      : dir_(std::move(dir)), made_(!std::filesystem::exists(dir_)) {
    std::filesystem::create_directories(dir_);
  }
  ~OutputFolder() {
    std::error_code ec;
    if (made_ && std::filesystem::is_empty(dir_, ec) && !ec) std::filesystem::remove(dir_, ec);
  }
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

 private:
  std::filesystem::path dir_;
  bool made_;
};

}  // namespace fieldlidar::app
