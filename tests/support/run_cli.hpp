#pragma once
// Running the fieldlidar executable from a test and capturing what it printed.

#include <sys/wait.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>

namespace fieldlidar::test {

struct CliResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

/// `p` in single quotes for the shell (a stream: GCC 12's -Wrestrict misfires on
/// `"'" + s + "'"` at -O3).
inline std::string quoted(const std::filesystem::path& p) {
  std::ostringstream s;
  s << '\'' << p.string() << '\'';
  return s.str();
}

/// Runs the shell command `cmd` (stderr should be sent to stdout by the caller: `2>&1`) and
/// returns its exit code and output.
inline CliResult run_shell(const std::string& cmd) {
  CliResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe)) r.output += buf.data();
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// Runs `fieldlidar ARGS` (ARGS is shell-quoted by the caller) and returns its exit code and
/// output.
inline CliResult run_cli(const std::string& args) {
  return run_shell(std::string(FIELDLIDAR_CLI) + " " + args + " 2>&1");
}

}  // namespace fieldlidar::test
