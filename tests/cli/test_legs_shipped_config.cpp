// fieldlidar legs finds its shipped classifier beside the executable (<prefix>/bin/fieldlidar ->
// <prefix>/share/fieldlidar/config), never at a compile-time path; a missing one is an error
// unless --no-classifier is given.

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

/// Runs `exe legs` on the annotated bag; the output file goes into `dir`.
test::CliResult run_legs(const fs::path& exe, const fs::path& dir, const std::string& extra) {
  const auto bag = test::data_file("legs_2d/positive_1_extracted.bag");
  const std::string cmd = test::quoted(exe) + " legs " + test::quoted(bag) +
                          " --topic /training_scan --force --out " +
                          test::quoted(dir / "legs.csv") + " " + extra + " 2>&1";
  test::CliResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe)) r.output += buf;
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

TEST(CliLegsShippedConfig, FoundBesideTheExecutableElseAnError) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d/positive_1_extracted.bag");
  const fs::path source_config = FIELDLIDAR_SOURCE_CONFIG_DIR;
  const auto prefix = test::temp_dir("legs_prefix");
  // A copy of the executable in PREFIX/bin (its libraries are found through the build RPATH).
  fs::create_directories(prefix / "bin");
  const auto exe = prefix / "bin" / "fieldlidar";
  fs::copy_file(FIELDLIDAR_CLI, exe, fs::copy_options::overwrite_existing);

  // Nothing in PREFIX/share: an error naming the folder searched and the way out.
  auto r = run_legs(exe, prefix, "");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find((prefix / "share" / "fieldlidar" / "config").string()), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("--no-classifier"), std::string::npos) << r.output;
  r = run_legs(exe, prefix, "--no-classifier");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("classifier none"), std::string::npos) << r.output;

  // Installed beside it: PREFIX/share/fieldlidar/config is used, not the source tree's.
  const auto share = prefix / "share" / "fieldlidar" / "config";
  fs::create_directories(share);
  for (const char* f : {"legs_2d.yaml", "legs_2d_classifier.yaml"})
    fs::copy_file(source_config / f, share / f);
  r = run_legs(exe, prefix, "");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("classifier " + (share / "legs_2d_classifier.yaml").string()),
            std::string::npos)
      << r.output;

  // The build-tree executable uses the source tree's config.
  r = run_legs(FIELDLIDAR_CLI, prefix, "");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("classifier " + (source_config / "legs_2d_classifier.yaml").string()),
            std::string::npos)
      << r.output;
}

}  // namespace
}  // namespace fieldlidar
