// Association, motion and tracking from trunks: small cases, and the simulated drive
// (`simulate --scene forest --frames 600 --seed 3`, VLP-16).
#include <cstdlib>

#include <gtest/gtest.h>

#include "tracking_eval.hpp"

namespace fieldlidar::forest::test {

TEST(ForestTrackingDrive, TrunksAlone) {
  const int frames = std::getenv("FOREST_FRAMES") ? std::atoi(std::getenv("FOREST_FRAMES")) : 600;
  const std::uint64_t seed = std::getenv("FOREST_SEED") ? std::atoi(std::getenv("FOREST_SEED")) : 3;
  const auto d = run_drive(seed, SensorModel::vlp16(), frames, false);
  std::printf("seed %d: ", int(seed));
  d.print("trunks alone, forest, VLP-16");
  if (frames < 600 || seed != 3) return;
  EXPECT_GE(d.path_m, 45.0);
  EXPECT_LE(d.drift_pct, 1.0);         // measured 0.583
  EXPECT_LE(d.deg_per_100m, 5.0);      // 2.65
  EXPECT_LE(d.end_error_m, 0.3);       // 0.111
  EXPECT_GE(d.map_recall(), 0.97);     // 1.000 (30 trees)
  EXPECT_GE(d.map_precision(), 0.97);  // 1.000 (30 of 30)
  EXPECT_LE(d.map_dbh_rmse(), 0.01);   // 0.0039
}

TEST(ForestTrackingDrive, TrunksWithOdometry) {
  const int frames = std::getenv("FOREST_FRAMES") ? std::atoi(std::getenv("FOREST_FRAMES")) : 600;
  const auto d = run_drive(3, SensorModel::vlp16(), frames, true);
  d.print("odometry + trunks, forest seed 3, VLP-16");
  if (frames < 600) return;
  EXPECT_LE(d.drift_pct, 1.0);        // measured 0.562
  EXPECT_LE(d.deg_per_100m, 5.0);     // 2.45
  EXPECT_LE(d.end_error_m, 0.3);      // 0.115
  EXPECT_GE(d.map_recall(), 0.97);    // 1.000
  EXPECT_LE(d.map_dbh_rmse(), 0.01);  // 0.0041
}

}  // namespace fieldlidar::forest::test
