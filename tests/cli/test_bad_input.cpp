// End-to-end: what fieldlidar does with a full disk, outputs it must not replace, and option
// values outside their range. Every failure is exit status 1, one "fieldlidar: error:" line
// naming the file or the option, and no output file left behind.

#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

/// Runs fieldlidar ARGS with the size of any file it writes limited to `kib` KiB (RLIMIT_FSIZE,
/// SIGXFSZ ignored): a write past it fails with EFBIG, as on a full disk.
test::CliResult run_limited(int kib, const std::string& args) {
  return test::run_shell("bash -c \"trap '' XFSZ; ulimit -f " + std::to_string(kib) + "; exec " +
                         std::string(FIELDLIDAR_CLI) + " " + args + "\" 2>&1");
}

std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += n + " ";
  return s;
}

TEST(CliBadInput, FullDiskFailsEveryWriterAndLeavesNoFile) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const auto in = test::data_file("kitti00/000000.bin");  // 124668 points, 1.9 MB
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"binary PLY", "convert " + test::quoted(in) + " OUT/x.ply"},
      {"ascii PLY", "convert " + test::quoted(in) + " OUT/x.ply --ascii"},
      {"PCD", "convert " + test::quoted(in) + " OUT/x.pcd"},
      {"KITTI bin", "convert " + test::quoted(in) + " OUT/x.bin"},
      {"label file", "segment " + test::quoted(in) + " --labels OUT/x.label"},
      {"PNG", "segment " + test::quoted(in) + " --png OUT/x.png"},
  };
  for (const auto& [what, args] : cases) {
    const auto dir = test::temp_dir("cli_full_disk");
    std::string a = args;
    a.replace(a.find("OUT"), 3, test::quoted(dir));
    const auto r = run_limited(8, a);  // 8 KiB: every output above is larger
    EXPECT_EQ(r.exit_code, 1) << what << ": " << r.output;
    EXPECT_NE(r.output.find("fieldlidar: error:"), std::string::npos) << what << ": " << r.output;
    EXPECT_NE(r.output.find("write failed"), std::string::npos) << what << ": " << r.output;
    EXPECT_TRUE(files_in(dir).empty()) << what << " left: " << joined(files_in(dir));
  }
}

/// Runs `script` (bash) in a private mount namespace with a 200 kB tmpfs mounted on `dir`, so
/// the test sees a real full file system (ENOSPC) without touching the machine's mounts; returns
/// its output, or nullopt when the test has no right to do that.
std::optional<std::string> on_small_tmpfs(const fs::path& dir, const std::string& script) {
  const std::string cmd = "unshare -m bash -c \"mount -t tmpfs -o size=200k tmpfs " +
                          test::quoted(dir) + " 2>/dev/null || exit 77; " + script + "\" 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return std::nullopt;
  std::string out;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int status = ::pclose(pipe);
  if (!WIFEXITED(status) || WEXITSTATUS(status) == 77 || out.find("unshare:") == 0)
    return std::nullopt;
  return out;
}

TEST(CliBadInput, FullFileSystemFailsAndLeavesNoFile) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const auto dir = test::temp_dir("cli_tmpfs");
  const std::string in = test::quoted(test::data_file("kitti00/000000.bin"));
  const std::string cli = FIELDLIDAR_CLI, d = test::quoted(dir);
  // Each command in turn on the full file system, its exit status, then what is left there.
  const auto out = on_small_tmpfs(
      dir, cli + " convert " + in + " " + d + "/x.ply; echo exit=\\$?; " + cli + " convert " + in +
               " " + d + "/x.ply --ascii; echo exit=\\$?; " + cli + " segment " + in + " --png " +
               d + "/x.png; echo exit=\\$?; ls -A " + d + "; echo end");
  if (!out) GTEST_SKIP() << "no right to mount a tmpfs in a private mount namespace (unshare -m)";
  EXPECT_EQ(out->find("exit=0"), std::string::npos) << *out;
  std::size_t errors = 0;
  for (auto at = out->find("No space left on device"); at != std::string::npos;
       at = out->find("No space left on device", at + 1))
    ++errors;
  EXPECT_EQ(errors, 3u) << *out;
  EXPECT_NE(out->find("exit=1\nend"), std::string::npos) << "files left: " << *out;
}

TEST(CliBadInput, ForceNeverReplacesSpecialFilesOrTheInput) {
  FIELDLIDAR_REQUIRE_DATA("kitti00/000000.bin");
  const auto dir = test::temp_dir("cli_force");
  const auto in = dir / "in.bin";
  fs::copy_file(test::data_file("kitti00/000000.bin"), in);
  const auto size = fs::file_size(in);
  const auto fifo = dir / "fifo.label", link = dir / "link.label", other = dir / "other.label";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  { std::ofstream(other) << "x"; }
  fs::create_symlink(other, link);
  std::vector<std::pair<std::string, std::string>> cases = {
      {"segment " + test::quoted(in) + " --labels " + test::quoted(fifo) + " -f", "FIFO"},
      {"segment " + test::quoted(in) + " --labels " + test::quoted(link) + " -f", "symbolic link"},
      {"convert " + test::quoted(in) + " " + test::quoted(in) + " -f", "is the input"},
      {"segment " + test::quoted(in) + " --out " + test::quoted(in) + " -f", "is the input"},
      {"segment " + test::quoted(in) + " --labels " + test::quoted(in) + " -f", "is the input"},
  };
  // A device node of our own (a copy of /dev/null), where the test may create one.
  const auto device = dir / "device.label";
  const bool have_device = ::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0;
  if (have_device)
    cases.emplace_back("segment " + test::quoted(in) + " --labels " + test::quoted(device) + " -f",
                       "device");
  else
    std::printf("[ skipped  ] the device-node case: no right to create one (mknod)\n");
  for (const auto& [args, why] : cases) {
    const auto r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.output;
    EXPECT_NE(r.output.find(why), std::string::npos) << args << ": " << r.output;
  }
  EXPECT_EQ(fs::file_size(in), size);
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  if (have_device) {
    EXPECT_TRUE(fs::is_character_file(fs::symlink_status(device)));
  }
  EXPECT_EQ(fs::file_size(other), 1u);
}

TEST(CliBadInput, SimulateChecksOptionsBeforeWritingAnything) {
  for (const std::string opt :
       {"--truth-resolution 0", "--dropout 2", "--imu-rate 0", "--odom-rate -1", "--noise -1"}) {
    const auto dir = test::temp_dir("cli_sim_options") / "out";
    const auto r =
        test::run_cli("simulate --scene terrain --frames 1 " + opt + " --out " + test::quoted(dir));
    EXPECT_EQ(r.exit_code, 1) << opt << ": " << r.output;
    const std::string name = opt.substr(0, opt.find(' '));
    EXPECT_NE(r.output.find("fieldlidar: error: " + name + ": must be"), std::string::npos)
        << opt << ": " << r.output;
    EXPECT_FALSE(fs::exists(dir)) << opt << ": the output folder was created";
  }
}

TEST(CliBadInput, OutOfRangeValuesAreRefusedNamingTheOption) {
  const auto dir = test::temp_dir("cli_ranges");
  const std::string out = test::quoted(dir / "o");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"segment x.bin --min-points -5", "--min-points"},
      {"segment x.bin --tolerance 0", "--tolerance"},
      {"follow --safe-distance -1 --out " + out, "--safe-distance"},
      {"follow --max-time -1 --out " + out, "--max-time"},
      {"follow --target-id -3 --out " + out, "--target-id"},
      {"legs x.bag --out " + out + " --truth-wedge 15 -15 5", "--truth-wedge"},
      {"legs x.bag --out " + out + " --truth-wedge -15 15 -5", "--truth-wedge"},
      {"legs x.bag --out " + out + " --match-radius -1", "--match-radius"},
      {"legs x.bag --out " + out + " --compact-occupancy nan", "--compact-occupancy"},
      {"legs x.bag --out " + out + " --occupied-leg nan nan", "--occupied-leg"},
      {"eval-tracking x.bag --compact-occupancy 2", "--compact-occupancy"},
      {"odometry x.bag -o " + out + " --elevation-correction nan", "--elevation-correction"},
      {"odometry x.bag -o " + out + " --initial-pose 0 0 inf 0 0 0", "--initial-pose"},
      {"simulate --scene lawn --out " + out + " --operator-speed -1", "--operator-speed"},
      {"simulate --scene lawn --out " + out + " --extra-walkers -3", "--extra-walkers"},
      {"simulate --scene lawn --out " + out + " --extra-walkers 100000", "--extra-walkers"},
      {"simulate --scene lawn --out " + out + " --frames 0", "--frames"},
      {"legs-train --sim-frames 2 --low-quantile 0.9 --high-quantile 0.1 --out " + out,
       "--low-quantile"},
      {"legs-train --sim-frames 2 --rounds 0 --out " + out, "--rounds"},
  };
  for (const auto& [args, option] : cases) {
    const auto r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.output;
    EXPECT_EQ(r.output.rfind("fieldlidar: error: " + option, 0), 0u) << args << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "o"));
  // The valid range is documented in --help.
  const auto help = test::run_cli("segment --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("--min-points UINT:whole number in [1, 100000000]"), std::string::npos)
      << help.output;
}

// The legs: map of a detector config is range-checked before any scan is read.
TEST(CliBadInput, LegsConfigOutOfRangeIsRefusedNamingKeyAndValue) {
  const auto dir = test::temp_dir("cli_legs_config");
  std::ofstream(dir / "legs.yaml") << "legs:\n  range_max_m: -5\n";
  const auto r =
      test::run_cli("legs x.bag --no-classifier --config " + test::quoted(dir / "legs.yaml") +
                    " --out " + test::quoted(dir / "o.csv"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("legs.yaml: leg detector setting range_max_m -5 must be above "
                          "range_min_m 0.3"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "o.csv"));
}

TEST(CliBadInput, ParseErrorsExitOneWithTheToolsWording) {
  for (const std::string args : {"segment", "segment x.bin --no-such-option", "no-such-command",
                                 "simulate --scene moon --out x"}) {
    const auto r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.output;
    EXPECT_EQ(r.output.rfind("fieldlidar: error: ", 0), 0u) << args << ": " << r.output;
  }
  EXPECT_EQ(test::run_cli("--help").exit_code, 0);
  EXPECT_EQ(test::run_cli("--version").exit_code, 0);
}

TEST(CliBadInput, EmptyScanIsSaidAndRingsUnknown) {
  const auto dir = test::temp_dir("cli_empty");
  const auto empty = dir / "empty.bin";
  { std::ofstream(empty, std::ios::binary); }
  auto r = test::run_cli("info " + test::quoted(empty));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + empty.string() + " holds no points"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("rings:   unknown"), std::string::npos) << r.output;
  r = test::run_cli("segment " + test::quoted(empty));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("no valid point"), std::string::npos) << r.output;
  r = test::run_cli("convert " + test::quoted(empty) + " " + test::quoted(dir / "e.pcd"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("has no points"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "e.pcd"));
}

TEST(CliBadInput, TimesOfAFolderWithoutStampsAreFlagged) {
  const auto dir = test::temp_dir("cli_unstamped");
  fs::create_directories(dir / "in");
  const float point[4] = {1, 2, 3, 0.5f};
  for (const char* name : {"000000.bin", "000001.bin"}) {
    std::ofstream f(dir / "in" / name, std::ios::binary);
    f.write(reinterpret_cast<const char*>(point), sizeof point);
  }
  const auto r =
      test::run_cli("convert " + test::quoted(dir / "in") + " " + test::quoted(dir / "out"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: 2 of 2 frames carry no time stamp"), std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "times.txt"));
  // The input folder itself as the output folder is refused.
  const auto same =
      test::run_cli("convert " + test::quoted(dir / "in") + " " + test::quoted(dir / "in") + " -f");
  EXPECT_EQ(same.exit_code, 1) << same.output;
  const auto glob = test::run_cli("convert " + test::quoted(dir / "in" / "*.bin") + " " +
                                  test::quoted(dir / "in") + " --format bin -f");
  EXPECT_EQ(glob.exit_code, 1) << glob.output;
  EXPECT_NE(glob.output.find("is the input folder"), std::string::npos) << glob.output;
  EXPECT_EQ(fs::file_size(dir / "in" / "000000.bin"), 16u);
}

}  // namespace
}  // namespace fieldlidar
