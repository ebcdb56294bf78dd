// The follow pipeline with a detector that tracks people itself (the 2D leg pipeline): a lost
// target whose own detector track is reported again is followed again at once, standing or not;
// another detector track in the same place is not taken.
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/follow/pipeline.hpp"

namespace fieldlidar::follow {
namespace {

Perception seen(const Eigen::Vector2d& p, std::int64_t id) {
  Perception out;
  out.people_m.push_back(p);
  out.people_ids.push_back(id);
  return out;
}

/// Runs the operator (detector id 7) 2 m ahead for 1 s, hidden for 1 s, then the detector
/// reports `back_id` standing 0.7 m to the side; the frames after that in which the mower
/// has a target.
int frames_held_after_return(std::int64_t back_id) {
  FollowPipeline pipeline(SensorModel::vlp16(), FollowConfig{});
  const Pose2 mower{};
  double t = 0;
  for (int k = 0; k < 10; ++k, t += 0.1) pipeline.follow(seen({2.0, 0.0}, 7), mower, t, 0.1);
  EXPECT_TRUE(pipeline.tracker().target_id().has_value());
  for (int k = 0; k < 10; ++k, t += 0.1) pipeline.follow(Perception{}, mower, t, 0.1);
  EXPECT_TRUE(pipeline.tracker().target_lost());
  int held = 0;
  for (int k = 0; k < 10; ++k, t += 0.1) {
    const auto out = pipeline.follow(seen({2.0, 0.7}, back_id), mower, t, 0.1);
    held += pipeline.tracker().target() != nullptr;
    if (pipeline.tracker().target()) {
      EXPECT_EQ(out.target_id, std::optional<std::uint32_t>(1u));
    }
  }
  return held;
}

TEST(FollowRetake, TheDetectorsOwnTrackOfTheTargetIsTakenBackAtOnce) {
  EXPECT_EQ(frames_held_after_return(7), 10);
}

TEST(FollowRetake, AnotherDetectorTrackInTheSamePlaceIsNotTaken) {
  // Standing, it never walks the 1 m a re-acquisition asks for.
  EXPECT_EQ(frames_held_after_return(8), 0);
}

}  // namespace
}  // namespace fieldlidar::follow
