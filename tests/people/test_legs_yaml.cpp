#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "fieldlidar/people/static_background.hpp"

namespace fieldlidar::people {
namespace {

TEST(LegsYaml, RoundTripsEveryField) {
  LegDetectorConfig c;
  c.curve_max = 1.75;
  c.path_min_m = 0.061;
  c.min_rings = 3;
  c.use_circle_fit = true;
  c.smooth_window = 5;
  const auto back = legs_config_from_yaml(to_yaml(c), "test");
  EXPECT_DOUBLE_EQ(back.curve_max, 1.75);
  EXPECT_DOUBLE_EQ(back.path_min_m, 0.061);
  EXPECT_EQ(back.min_rings, 3);
  EXPECT_TRUE(back.use_circle_fit);
  EXPECT_EQ(back.smooth_window, 5);
  EXPECT_EQ(to_yaml(back), to_yaml(c));
}

TEST(LegsYaml, UnknownKeysAndBadValuesNameTheSource) {
  try {
    legs_config_from_yaml("legs:\n  curvy: 2\n", "my.yaml");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("my.yaml: unknown leg detector setting 'curvy'"),
              std::string::npos);
  }
  EXPECT_THROW(legs_config_from_yaml("legs:\n  curve_max: abc\n", "x"), Error);
  EXPECT_THROW(legs_config_from_yaml("legs:\n  path_min_m: 0.5\n  path_max_m: 0.2\n", "x"), Error);
  EXPECT_DOUBLE_EQ(legs_config_from_yaml("curve_max: 2.5\n", "x").curve_max, 2.5);  // bare map
}

// Values the detector would run with and find nothing (or crawl): refused, naming key and value.
TEST(LegsYaml, OutOfRangeSettingsNameTheKeyAndTheValue) {
  const struct {
    const char* yaml;
    const char* message;
  } cases[] = {
      {"range_max_m: -5", "range_max_m -5 must be above range_min_m 0.3"},
      {"range_min_m: 0", "range_min_m 0 must be positive"},
      {"range_min_m: 20", "range_max_m 15 must be above range_min_m 20"},
      {"segment_jump_m: 0", "segment_jump_m 0 must be positive"},
      {"min_points: 0", "min_points 0 must lie in [1, 10000]"},
      {"smooth_window: 1000000000", "smooth_window 1000000000 must be an odd number in [1, 99]"},
      {"smooth_window: 4", "smooth_window 4 must be an odd number"},
      {"curve_max: 1", "curve_max 1 must be above 1"},
      {"pair_distance_max_m: 0", "pair_distance_max_m 0 must be positive"},
      {"min_rings: 0", "min_rings 0 must be at least 1"},
      {"leg_merge_radius_m: -1", "leg_merge_radius_m -1 must be positive"},
      {"split_azimuth_gap_rad: 7", "split_azimuth_gap_rad 7 must lie in [0, 2 pi]"},
      {"path_step_m: -0.1", "path_step_m -0.1 must not be negative"},
      {"chord_max_m: 0", "chord_max_m 0 must be positive"},
      {"use_circle_fit: true\n  radius_min_m: 0.2\n  radius_max_m: 0.1",
       "radius_min_m 0.2 must be below radius_max_m 0.1"},
      {"circle_rms_max_m: 0", "circle_rms_max_m 0 must be positive"},
      {"use_curve_min: true\n  curve_min: 2", "curve_min 2 must be below curve_max 1.9"},
      {"foreground_margin_m: -1", "foreground_margin_m -1 must not be negative"},
  };
  for (const auto& c : cases) {
    try {
      legs_config_from_yaml(std::string("legs:\n  ") + c.yaml + "\n", "site.yaml");
      ADD_FAILURE() << c.yaml << ": accepted";
    } catch (const Error& e) {
      EXPECT_NE(
          std::string(e.what()).find(std::string("site.yaml: leg detector setting ") + c.message),
          std::string::npos)
          << c.yaml << ": " << e.what();
    }
  }
  // A test switched off need not have its bounds in order.
  EXPECT_NO_THROW(legs_config_from_yaml(
      "legs:\n  use_circle_fit: false\n  radius_min_m: 0.2\n  radius_max_m: 0.1\n", "x"));
}

TEST(Matching, OneToOneWithinTheRadius) {
  const std::vector<Eigen::Vector2d> det{{0, 0}, {0.1, 0}, {5, 5}};
  const std::vector<Eigen::Vector2d> truth{{0.05, 0}, {1, 1}};
  const auto m = match_points(det, truth, 0.15);
  EXPECT_EQ(m.true_positive, 1u);
  EXPECT_EQ(m.false_positive, 2u);
  EXPECT_EQ(m.false_negative, 1u);
  EXPECT_DOUBLE_EQ(m.precision(), 1.0 / 3);
  EXPECT_DOUBLE_EQ(m.recall(), 0.5);
}

}  // namespace
}  // namespace fieldlidar::people

namespace fieldlidar::people {
namespace {

TEST(StaticBackground, StillObjectsBecomeBackgroundWalkersDoNot) {
  StaticBackground bg;
  const std::vector<Eigen::Vector2d> post{{2.0, 1.0}, {2.02, 1.01}};
  for (int k = 0; k < 40; ++k) {
    std::vector<Eigen::Vector2d> scan = post;
    scan.emplace_back(-3.0 + 0.1 * k, 2.0);  // a walker at 1 m/s (10 Hz)
    if (k == 10) {
      EXPECT_FALSE(bg.is_static(post));  // still warming up
    }
    bg.update(scan);
  }
  EXPECT_TRUE(bg.is_static(post));
  EXPECT_FALSE(bg.is_static(std::vector<Eigen::Vector2d>{{-3.0 + 0.1 * 39, 2.0}}));
  EXPECT_FALSE(bg.is_static(std::vector<Eigen::Vector2d>{{5.0, 5.0}}));
  // A cell never hit (it shares its slot with the post's cell 40 m away): not background.
  EXPECT_FALSE(bg.is_static(std::vector<Eigen::Vector2d>{{42.0, 1.0}}));
}

// The grid rolls with the sensor: a post 60 m from the origin (outside the first 40 m square)
// becomes background, and the cells it reuses forget what they held before.
TEST(StaticBackground, GridFollowsTheSensorFarFromTheOrigin) {
  StaticBackground bg;
  const std::vector<Eigen::Vector2d> near_post{{2.0, 1.0}}, far_post{{62.0, 1.0}};
  for (int k = 0; k < 40; ++k) bg.update(near_post);
  EXPECT_TRUE(bg.is_static(near_post));
  EXPECT_FALSE(bg.is_static(far_post));
  for (int k = 0; k < 200; ++k) bg.update(far_post);
  EXPECT_TRUE(bg.is_static(far_post));
  // 62 m and 22 m share a slot (40 m grid); 2 m was decayed and is not overwritten.
  EXPECT_FALSE(bg.is_static(std::vector<Eigen::Vector2d>{{22.0, 1.0}}));
  EXPECT_FALSE(bg.is_static(std::vector<Eigen::Vector2d>{{-1e7, 0.0}}));
}

}  // namespace
}  // namespace fieldlidar::people
