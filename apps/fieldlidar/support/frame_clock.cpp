#include "support/frame_clock.hpp"

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::app {

void stamp_at_rate(io::Frame& frame, double rate_hz, std::optional<double>& first_stamp_s) {
  if (rate_hz <= 0) return;
  if (!first_stamp_s) first_stamp_s = frame.stamp_s;
  frame.stamp_s = frame.cloud.stamp_s = *first_stamp_s + double(frame.index) / rate_hz;
}

void FrameClock::check(const io::Frame& frame) {
  if (last_stamp_s_ && frame.stamp_s < *last_stamp_s_)
    throw Error(
        fmt::format("{}: frame {} is stamped {:.6f} s, before the frame ahead of it "
                    "({:.6f} s)",
                    input_, frame.index, frame.stamp_s, *last_stamp_s_));
  repeats_ = last_stamp_s_ && frame.stamp_s == *last_stamp_s_ ? repeats_ + 1 : 0;
  if (repeats_ + 1 >= kMaxFramesWithoutTime)
    throw Error(
        fmt::format("{}: {} frames in a row carry the same stamp ({:.6f} s): people are "
                    "tracked by time; {}",
                    input_, repeats_ + 1, frame.stamp_s, hint_));
  last_stamp_s_ = frame.stamp_s;
}

}  // namespace fieldlidar::app
