// A program that links fieldlidar::follow alone runs the follow pipeline without loading the
// simulator (DESIGN.md: the closed loop over sim/ lives in loops/). The configuration checks the
// same on the CMake targets (fieldlidar_assert_not_linked); this checks the built libraries.

#include <link.h>

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/follow/pipeline.hpp"

namespace fieldlidar::follow {
namespace {

std::vector<std::string> loaded_objects() {
  std::vector<std::string> names;
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        static_cast<std::vector<std::string>*>(data)->push_back(info->dlpi_name ? info->dlpi_name
                                                                                : "");
        return 0;
      },
      &names);
  return names;
}

TEST(FollowWithoutSim, PipelineRunsAndTheSimulatorIsNotLoaded) {
  const SensorModel sensor = SensorModel::vlp16();
  FollowPipeline pipeline(sensor, FollowConfig{});
  const auto out = pipeline.step(PointCloud{}, Pose::Identity(), Pose2{}, 0.0, 0.1);
  EXPECT_FALSE(out.target_id.has_value());
  bool follow_shared = false;
  for (const auto& name : loaded_objects()) {
    EXPECT_EQ(name.find("libfieldlidar_sim"), std::string::npos) << name << " is loaded";
    follow_shared = follow_shared || name.find("libfieldlidar_follow") != std::string::npos;
  }
  if (!follow_shared) GTEST_SKIP() << "static build: the CMake configuration checked the links";
}

}  // namespace
}  // namespace fieldlidar::follow
