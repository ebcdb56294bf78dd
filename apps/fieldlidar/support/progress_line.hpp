#pragma once
/// \file A progress line on stderr ("frame 120 (40 %) ..."), rewritten in place with a carriage
/// return, and written only when stderr is a terminal: a log file or a CI job's output gets the
/// results and the warnings, not one line of every frame's carriage returns.

#include <cstdio>
#include <utility>

#include <fmt/core.h>

namespace fieldlidar::app {

/// True when stderr is a terminal.
bool stderr_is_terminal();

class ProgressLine {
 public:
  ProgressLine() : on_(stderr_is_terminal()) {}
  /// Rewrites the line (nothing when stderr is not a terminal).
  template <class... Args>
  void show(fmt::format_string<Args...> format, Args&&... args) {
    if (!on_) return;
    fmt::print(stderr, "\r");
    fmt::print(stderr, format, std::forward<Args>(args)...);
    std::fflush(stderr);
    open_ = true;
  }
  /// Back to the line's start, so that a warning printed now overwrites it.
  void interrupt() {
    if (open_) fmt::print(stderr, "\r");
  }
  /// Ends the line once something was shown.
  void end() {
    if (open_) fmt::print(stderr, "\n");
    open_ = false;
  }

 private:
  bool on_ = false;
  bool open_ = false;
};

}  // namespace fieldlidar::app
