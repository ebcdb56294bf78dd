// KITTI tracking labels: rows, 3D boxes in the rectified camera frame, point-in-box.
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/kitti_tracking_labels.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

TEST(KittiTrackingLabels, RowsAndBoxes) {
  const std::string text =
      "0 -1 DontCare -1 -1 -10 219.3 188.5 245.5 218.6 -1000 -1000 -1000 -10 -1 -1 -1\n"
      "0 2 Pedestrian 0 0 -2.52 1106.1 166.6 1204.5 323.9 1.714 0.768 0.972 6.302 1.652 8.456 "
      "-1.900\n";
  const auto rows = io::parse_kitti_tracking_labels(text, "labels.txt");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_FALSE(rows[0].has_box());
  const auto& p = rows[1];
  EXPECT_EQ(p.type, "Pedestrian");
  EXPECT_EQ(p.track_id, 2);
  EXPECT_DOUBLE_EQ(p.h_m, 1.714);
  // The box stands on (x, y, z), y down: its centre is h/2 above, inside; 5 cm below the
  // bottom face is outside; a point 0.45 m beside the centre along the length (l/2 = 0.486)
  // rotated by ry is inside.
  EXPECT_TRUE(p.contains(p.center_rect_m()));
  EXPECT_FALSE(p.contains(p.bottom_rect_m + Eigen::Vector3d(0, 0.05, 0)));
  EXPECT_TRUE(p.contains(p.bottom_rect_m + Eigen::Vector3d(0, 0.05, 0), 0.1));
  const Eigen::Vector3d along_l(std::cos(p.ry_rad), 0, -std::sin(p.ry_rad));
  EXPECT_TRUE(p.contains(p.center_rect_m() + 0.45 * along_l));
  EXPECT_FALSE(p.contains(p.center_rect_m() + 0.55 * along_l));
  EXPECT_THROW(io::parse_kitti_tracking_labels("0 2 Pedestrian 0 0\n", "bad.txt"), Error);
}

TEST(KittiTrackingLabels, NegativeFrameAndBoxSizeAreRefusedByLine) {
  const std::string dont_care =
      "0 -1 DontCare -1 -1 -10 219 188 245 218 -1000 -1000 -1000 -10 -1 -1 -1\n";
  const struct {
    std::string row, message;
  } cases[] = {
      {"-5 2 Pedestrian 0 0 -2.5 1106 166 1204 323 1.7 0.7 0.9 6.3 1.6 8.4 -1.9\n",
       "l.txt: line 2: frame -5 is negative"},
      {"0 2 Pedestrian 0 0 -2.5 1106 166 1204 323 -1.7 -0.5 -0.8 6.3 1.6 8.4 -1.9\n",
       "l.txt: line 2: Pedestrian box size h -1.7 w -0.5 l -0.8 m is not positive"},
      {"0 3 Car 0 0 -2.5 1106 166 1204 323 1.5 0 3.9 6.3 1.6 8.4 -1.9\n",
       "l.txt: line 2: Car box size h 1.5 w 0 l 3.9 m is not positive"},
  };
  for (const auto& c : cases) {
    try {
      io::parse_kitti_tracking_labels(dont_care + c.row, "l.txt");
      ADD_FAILURE() << c.row << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(io::parse_kitti_tracking_labels(dont_care, "l.txt").size(), 1u);  // -1 sizes: fine
}

TEST(KittiTrackingLabels, SharedSequenceLabels) {
  const char* f = "kitti_tracking0000/label_02_0000_frames0-49.txt";
  FIELDLIDAR_REQUIRE_DATA(f);
  const auto rows = io::read_kitti_tracking_labels(test::data_file(f));
  int pedestrians = 0, cyclists = 0;
  for (const auto& r : rows) {
    EXPECT_LT(r.frame, 50);
    pedestrians += r.type == "Pedestrian";
    cyclists += r.type == "Cyclist";
  }
  EXPECT_EQ(pedestrians, 6);  // data README
  EXPECT_EQ(cyclists, 50);
}

}  // namespace
}  // namespace fieldlidar
