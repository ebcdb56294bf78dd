// The person tracker's `tracker:` map in a leg detector YAML file: every field round-trips, bad
// settings are errors naming the file and the key, the shipped file states the 2D pipeline's
// defaults, and a setting read from text changes what the tracker does.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/people/joint_tracker_yaml.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "fieldlidar/people/legs_2d_pipeline.hpp"

namespace fieldlidar::people {
namespace {

std::string error_of(const std::string& text) {
  try {
    joint_tracker_config_from_yaml(text, "site.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(TrackerYaml, RoundTripsEveryField) {
  JointTrackerConfig c;
  c.min_travel_m = 0.75;
  c.confirm_hits = 6;
  c.zone_half_angle_deg = 30;
  c.standing_leg_width_max_m = 0.18;
  const auto back = joint_tracker_config_from_yaml(to_yaml(c), "test");
  EXPECT_DOUBLE_EQ(back.min_travel_m, 0.75);
  EXPECT_EQ(back.confirm_hits, 6);
  EXPECT_DOUBLE_EQ(back.zone_half_angle_deg, 30);
  EXPECT_DOUBLE_EQ(back.standing_leg_width_max_m, 0.18);
  EXPECT_EQ(to_yaml(back), to_yaml(c));
}

TEST(TrackerYaml, NoMapKeepsTheBaseAndTheLegsReaderSkipsIt) {
  JointTrackerConfig base;
  base.confirm_hits = 9;
  EXPECT_EQ(joint_tracker_config_from_yaml("legs:\n  curve_max: 2\n", "x", base).confirm_hits, 9);
  EXPECT_EQ(joint_tracker_config_from_yaml("", "x", base).confirm_hits, 9);
  // The bare form (leg settings at the root) may carry a tracker map beside them.
  const std::string bare = "curve_max: 2.5\ntracker:\n  confirm_hits: 3\n";
  EXPECT_DOUBLE_EQ(legs_config_from_yaml(bare, "x").curve_max, 2.5);
  EXPECT_EQ(joint_tracker_config_from_yaml(bare, "x").confirm_hits, 3);
  EXPECT_THROW(legs_config_from_yaml("not a map", "x"), Error);
}

TEST(TrackerYaml, BadSettingsNameTheFileAndTheKey) {
  EXPECT_NE(error_of("tracker:\n  confirm_hit: 3\n")
                .find("site.yaml: unknown tracker setting "
                      "'confirm_hit'"),
            std::string::npos);
  EXPECT_NE(error_of("tracker:\n  gate_m: wide\n").find("'gate_m' has a bad value 'wide'"),
            std::string::npos);
  EXPECT_NE(error_of("tracker:\n  gate_m: .nan\n").find("'gate_m' has a bad value"),
            std::string::npos);
  EXPECT_NE(error_of("tracker:\n  gate_m: 0\n").find("gate_m must be positive"), std::string::npos);
  EXPECT_NE(error_of("tracker:\n  evidence_decay: 1.5\n").find("evidence_decay"),
            std::string::npos);
  EXPECT_NE(error_of("tracker:\n  zone_range_min_m: 4\n").find("zone_range_max_m"),
            std::string::npos);
  EXPECT_NE(error_of("tracker:\n  confirm_hits: -2\n").find("confirm_hits"), std::string::npos);
  EXPECT_NE(error_of("tracker: 3\n").find("expected a map of tracker settings"), std::string::npos);
}

// The shipped 2D config states the tracker settings the 2D pipeline runs with, so a user who
// copies it starts from what is measured in docs/people.md.
TEST(TrackerYaml, ShippedConfigStatesThePipelineDefaults) {
  std::ifstream in(std::string(FIELDLIDAR_CONFIG_DIR) + "/legs_2d.yaml");
  ASSERT_TRUE(in.good());
  std::stringstream ss;
  ss << in.rdbuf();
  const LegPipeline2DConfig defaults;
  const auto shipped =
      joint_tracker_config_from_yaml(ss.str(), "legs_2d.yaml", JointTrackerConfig{});
  EXPECT_EQ(to_yaml(shipped), to_yaml(defaults.joint));
  EXPECT_NO_THROW(legs_config_from_yaml(ss.str(), "legs_2d.yaml"));
}

// A pair of legs standing 3 m to the side (out of the follow zone): reported after the
// standing pairs the file asks for, not the default.
TEST(TrackerYaml, ASettingFromTheFileChangesWhenAPersonIsReported) {
  auto first_report = [](const JointTrackerConfig& c) {
    JointPersonTracker tracker(c);
    for (int k = 0; k < 30; ++k) {
      // Scores of 0.5: a confidence that never reaches strong_evidence (5) by itself.
      const std::vector<LegObservation> legs{{{0.0, 3.0}, 0.5, 0.1}, {{0.0, 3.3}, 0.5, 0.1}};
      if (!tracker.update(0.1 * k, legs, Eigen::Isometry2d::Identity()).reported.empty()) return k;
    }
    return -1;
  };
  const int by_default = first_report(JointTrackerConfig{});
  const int from_file = first_report(
      joint_tracker_config_from_yaml("tracker:\n  standing_pair_hits: 10\n", "site.yaml"));
  EXPECT_EQ(by_default, 3);  // confirm_hits 4: its fourth scan
  EXPECT_EQ(from_file, 9);   // its tenth
}

}  // namespace
}  // namespace fieldlidar::people
