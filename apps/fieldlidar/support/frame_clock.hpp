#pragma once
// The frames' clock for commands that track people over time: stamps must not go backwards,
// and a run of frames with one stamp means the input has no clock (a folder of frame files
// without a times.txt), under which tracks would never age out.

#include <optional>
#include <string>

#include "fieldlidar/io/frame_source.hpp"

namespace fieldlidar::app {

/// `--rate HZ`: stamps `frame` `index / rate_hz` after the first frame's own stamp (kept in
/// `first_stamp_s`), for frames without a clock; nothing when rate_hz <= 0.
void stamp_at_rate(io::Frame& frame, double rate_hz, std::optional<double>& first_stamp_s);

class FrameClock {
 public:
  /// `input` names the input in errors; `hint` tells how to give the frames a clock.
  FrameClock(std::string input, std::string hint)
      : input_(std::move(input)), hint_(std::move(hint)) {}
  /// Throws fieldlidar::Error when `frame` is stamped before the frame ahead of it, or when it is
  /// the kMaxFramesWithoutTime-th frame in a row with the same stamp.
  void check(const io::Frame& frame);

  /// Frames in a row with one stamp taken as a duplicate or two; more is no clock at all.
  static constexpr int kMaxFramesWithoutTime = 10;

 private:
  std::string input_, hint_;
  std::optional<double> last_stamp_s_;
  int repeats_ = 0;  ///< frames in a row stamped as the one before
};

}  // namespace fieldlidar::app
