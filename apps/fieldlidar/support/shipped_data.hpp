#pragma once
// Where the data files shipped with fieldlidar (config/: the 2D leg detector and its classifier)
// are, for an installed executable and for one run from its build tree.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace fieldlidar::app {

/// The folders searched for shipped config files, in order: <prefix>/share/fieldlidar/config of
/// the running executable (<prefix>/bin/fieldlidar, resolved through /proc/self/exe, so a
/// relocated install finds its own files), then, only when the executable is the one in its build
/// tree, the source tree's config/.
std::vector<std::filesystem::path> shipped_config_dirs();

/// The first of shipped_config_dirs() holding `file`; nullopt when none does.
std::optional<std::filesystem::path> find_shipped_config(const std::string& file);

}  // namespace fieldlidar::app
