#include "support/shipped_data.hpp"

#include <system_error>

namespace fieldlidar::app {

namespace fs = std::filesystem;

std::vector<fs::path> shipped_config_dirs() {
  std::vector<fs::path> dirs;
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  if (ec) return dirs;
  const fs::path bin = exe.parent_path();
  dirs.push_back((bin / FIELDLIDAR_BIN_TO_CONFIG).lexically_normal());
  // A build-tree executable uses the sources it was built from (never an installed one: a copy
  // of the executable elsewhere must not pick up a source tree that happens to exist).
  const fs::path build_bin = fs::weakly_canonical(FIELDLIDAR_BUILD_BIN_DIR, ec);
  if (!ec && bin == build_bin) dirs.emplace_back(FIELDLIDAR_SOURCE_CONFIG_DIR);
  return dirs;
}

std::optional<fs::path> find_shipped_config(const std::string& file) {
  for (const auto& dir : shipped_config_dirs()) {
    std::error_code ec;
    if (fs::is_regular_file(dir / file, ec)) return dir / file;
  }
  return std::nullopt;
}

}  // namespace fieldlidar::app
