// Ground segmentation: synthetic scans with exact truth and the real RELLIS-3D off-road frame.

#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/segmentation/segment.hpp"
#include "seg_test_util.hpp"
#include "test_data.hpp"

namespace fieldlidar::segmentation {
namespace {

using test::Box;
using test::synthetic_scan;

GroundScore score_synthetic(const PointCloud& cloud, const GroundResult& r) {
  const std::vector<std::uint16_t> ground{1}, ignored{0};
  return score_ground(cloud, r.is_ground, cloud.labels, ground, ignored);
}

std::vector<Box> yard() {
  // A car-sized box, a post, a low kerb-like step and a person-sized box, on ground at -h.
  return {{{6, -2, -2.0}, {10, 0, -0.5}},
          {{-4, 3, -2.0}, {-3.8, 3.2, 1.0}},
          {{2, 5, -2.0}, {8, 5.4, -0.6}},
          {{-6, -3, -2.0}, {-5.6, -2.6, -0.2}}};
}

TEST(Ground, EveryMethodFindsFlatGround) {
  const double h = 1.0;
  SensorModel vlp = SensorModel::vlp16();
  vlp.mounting_height_m = h;
  const PointCloud cloud = synthetic_scan(
      vlp, [h](double, double) { return -h; }, yard(), true, 0.01);
  for (GroundMethod m : {GroundMethod::kRobust, GroundMethod::kSeed000, GroundMethod::kSeed002}) {
    GroundConfig cfg;
    cfg.method = m;
    const GroundResult r = segment_ground(cloud, vlp, cfg);
    ASSERT_EQ(r.is_ground.size(), cloud.size());
    const GroundScore s = score_synthetic(cloud, r);
    EXPECT_GT(s.f1, 0.97) << "method " << int(m) << " P " << s.precision << " R " << s.recall;
  }
}

TEST(Ground, RobustEstimatesTheSensorHeightInsteadOfTrustingIt) {
  const double h = 1.2;
  SensorModel vlp = SensorModel::vlp16();
  vlp.mounting_height_m = 1.8;  // wrong by half
  const PointCloud cloud = synthetic_scan(
      vlp, [h](double, double) { return -h; }, yard(), true, 0.01);
  const GroundResult r = ground_robust(cloud, vlp);
  EXPECT_NEAR(r.sensor_height_m, h, 0.05);
  EXPECT_GT(score_synthetic(cloud, r).f1, 0.98);
  EXPECT_NEAR(estimate_sensor_height(cloud), h, 0.05);
  // The seed 002 rule with too large an H misses all ground: it is only as good as H.
  EXPECT_LT(score_synthetic(cloud, ground_seed002(cloud, vlp)).recall, 0.1);
}

TEST(Ground, RobustFollowsASlopeAndARollingHill) {
  // 8 degree incline along x plus a 0.6 m bump, vehicle standing on it.
  const double h = 1.0, grade = std::tan(8.0 * std::numbers::pi / 180.0);
  auto ground = [&](double x, double y) {
    return -h + grade * x + 0.6 * std::exp(-((x + 12) * (x + 12) + y * y) / 30.0);
  };
  const SensorModel hdl = SensorModel::hdl32e();
  std::vector<Box> boxes = {{{5, -3, ground(5, -3) - 0.5}, {7, -1, ground(7, -1) + 1.5}}};
  const PointCloud cloud = synthetic_scan(hdl, ground, boxes, true, 0.01);
  const GroundScore robust = score_synthetic(cloud, ground_robust(cloud, hdl));
  EXPECT_GT(robust.f1, 0.97) << "P " << robust.precision << " R " << robust.recall;
  // A level H - h test cannot follow the slope.
  const GroundScore seed002 = score_synthetic(cloud, ground_seed002(cloud, hdl));
  EXPECT_LT(seed002.f1, robust.f1 - 0.2);
}

// A VLP-16 on flat ground 2 m from a hill's foot: the ground curves up ahead (to 20 deg at 8 m;
// flat elsewhere) and no ring meets it nearer than the blind radius r_b (4.5 m on a 1.2 m
// mast), so the first ground seen that way stands above the plane of the ground round the
// robot. It continues the ground; a rock as high on the flat ground behind the robot (ground
// beyond it lower) does not. The same hill for a sparse sensor that sees nearer (HDL-32E, r_b
// 2.0 m) and a dense one (OS1-64, 4.0 m), its foot as far inside their blind disk (rock
// returns taken for ground there are the rock's foot, the same with the rule or without).
TEST(Ground, FirstGroundUpAHillsFootFromTheBlindDisk) {
  const double h = 1.2, k = 0.06;
  for (const SensorModel& sensor :
       {SensorModel::vlp16(), SensorModel::hdl32e(), SensorModel::os1_64()}) {
    const double shift = sensor.ground_reach_m(h) - SensorModel::vlp16().ground_reach_m(h);
    const double foot = 2.0 + shift;
    auto ground = [&](double x, double y) {  // the hill ahead only, about 6 m wide
      return x > foot ? -h + 0.5 * k * (x - foot) * (x - foot) * std::exp(-y * y / 8.0) : -h;
    };
    const std::vector<Box> rock = {{{-7.0, -0.5, -h - 0.1}, {-6.4, 0.5, -h + 0.35}}};
    const PointCloud cloud = synthetic_scan(sensor, ground, rock, true, 0.01);
    const auto hill_recall = [&](const GroundResult& r) {
      std::size_t n = 0, hit = 0;
      for (std::size_t i = 0; i < cloud.size(); ++i) {
        const auto& p = cloud.points[i];
        if (!p.is_valid() || (cloud.labels[i] & 0xffff) != 1 || p.x > 8.0 + shift ||
            std::abs(p.y) > 1.5)
          continue;
        ++n;
        hit += r.is_ground[i];
      }
      return n ? double(hit) / double(n) : 0.0;
    };
    const auto rock_ground = [&](const GroundResult& r) {
      std::size_t n = 0;
      for (std::size_t i = 0; i < cloud.size(); ++i)
        n += (cloud.labels[i] & 0xffff) != 1 && cloud.points[i].is_valid() && r.is_ground[i];
      return n;
    };
    RobustGroundConfig off;
    off.first_cell_max_rise_m = 0.0;
    const GroundResult with = ground_robust(cloud, sensor),
                       without = ground_robust(cloud, sensor, off);
    std::printf(
        "%s, hill's foot %.1f m ahead: ground recall %.3f (%.3f without); rock returns taken "
        "for ground %zu (%zu without)\n",
        sensor.name.c_str(), foot, hill_recall(with), hill_recall(without), rock_ground(with),
        rock_ground(without));
    EXPECT_GT(hill_recall(with), 0.9) << sensor.name;
    // The dense sensor's multi-ring cells follow this hill without the rule (0.966 either way);
    // the sparse ones lose a third (VLP-16 0.916 / 0.573) or a quarter (HDL-32E 0.926 / 0.689).
    if (sensor.rings() <= 32) {
      const double gain = sensor.rings() <= 16 ? 0.3 : 0.2;
      EXPECT_LT(hill_recall(without), hill_recall(with) - gain) << sensor.name;
    }
    EXPECT_EQ(rock_ground(with), rock_ground(without)) << sensor.name;
  }
}

TEST(Ground, UndercutTestRejectsShrubFeetAndKeepsTheGroundUnderAHedge) {
  // A VLP-16 0.45 m above flat ground (a mower). In front, shrubs whose foot is narrower than
  // their body: the lowest ring hits the foot a few centimetres above the ground, the next ring
  // the body nearer the sensor. Behind, a hedge cut 5 cm above the ground, the ground running on
  // under it.
  const double h = 0.45;
  const SensorModel vlp = SensorModel::vlp16();
  std::vector<Box> boxes;
  for (double y : {-6.0, -3.0, 0.0, 3.0, 6.0}) {
    boxes.push_back({{3.0, y - 0.4, -h - 0.1}, {3.8, y + 0.4, -h + 0.08}});
    boxes.push_back({{2.85, y - 0.5, -h + 0.08}, {3.8, y + 0.5, -h + 0.25}});
    boxes.push_back({{2.7, y - 0.6, -h + 0.25}, {3.8, y + 0.6, -h + 0.8}});
    boxes.push_back({{-3.8, y - 0.6, -h + 0.05}, {-3.0, y + 0.6, -h + 0.8}});
  }
  const PointCloud cloud = synthetic_scan(
      vlp, [h](double, double) { return -h; }, boxes, true, 0.01);
  auto score = [&](const RobustGroundConfig& cfg) {
    return score_synthetic(cloud, ground_robust(cloud, vlp, cfg));
  };
  const GroundScore with = score({});
  RobustGroundConfig no_face;
  no_face.face_columns = 0;
  RobustGroundConfig no_undercut;
  no_undercut.face_back_rise_m = 1e9;
  RobustGroundConfig no_flat_run;
  no_flat_run.face_back_flat_m = -1.0;
  const GroundScore without = score(no_face), steep_only = score(no_undercut),
                    no_flat = score(no_flat_run);
  // Measured: 194 false positives with the test, 557 without it, 401 with the steep-face part
  // only; no ground lost, 9 ground returns under the hedge lost without the flat-run rule.
  EXPECT_LT(with.false_positive * 2, without.false_positive);
  EXPECT_LT(double(with.false_positive), 0.6 * double(steep_only.false_positive));
  EXPECT_EQ(with.false_negative, 0u);
  EXPECT_EQ(without.false_negative, 0u);
  EXPECT_GT(no_flat.false_negative, 0u);
}

TEST(Ground, GroundRunningOnToTheFootOfABushStaysGround) {
  // A VLP-16 1.2 m above flat ground. Four bushes stand with their faces where the -7 deg ring
  // meets the ground (9.78 m), so the -5 deg ring strikes each face 0.34 m straight above that
  // ground return: a steep pair whose lower return continues the ground of the -9 deg ring
  // 2.2 m nearer.
  const double h = 1.2, face = 9.78;
  const SensorModel vlp = SensorModel::vlp16();
  const std::vector<Box> boxes = {{{face, -0.6, -h}, {face + 1.2, 0.6, -h + 1.0}},
                                  {{-face - 1.2, -0.6, -h}, {-face, 0.6, -h + 1.0}},
                                  {{-0.6, face, -h}, {0.6, face + 1.2, -h + 1.0}},
                                  {{-0.6, -face - 1.2, -h}, {0.6, -face, -h + 1.0}}};
  const PointCloud cloud = synthetic_scan(
      vlp, [h](double, double) { return -h; }, boxes, true, 0.005);
  const GroundScore with = score_synthetic(cloud, ground_robust(cloud, vlp));
  RobustGroundConfig across_shadow_only;
  across_shadow_only.face_flat_gap_m = 0.0;
  const GroundScore without = score_synthetic(cloud, ground_robust(cloud, vlp, across_shadow_only));
  std::printf("foot of a bush: FN %zu (without the run-on rule %zu), FP %zu (%zu)\n",
              std::size_t(with.false_negative), std::size_t(without.false_negative),
              std::size_t(with.false_positive), std::size_t(without.false_positive));
  // Measured: no ground lost; 128 ground returns (the -7 deg ring in front of the four faces)
  // lost when the lower return of a steep pair is always taken for the face's foot.
  EXPECT_EQ(with.false_negative, 0u);
  EXPECT_GE(without.false_negative, 100u);
  EXPECT_EQ(with.false_positive, without.false_positive);
}

TEST(Ground, FollowsTheGroundFallingAwayBehindACrest) {
  // A VLP-16 1.2 m above a level top that ends 7 m out; beyond, the ground falls at 25 deg to a
  // valley floor 2 m lower. The drop is out of sight: the -9 deg ring passes over the crest and
  // meets the valley floor 20 m out, 14 m beyond the last ground return (-11 deg). A box 1 m
  // tall stands on the floor 30-31 m out.
  const double h = 1.2, crest = 7.0, drop = 2.0;
  auto ground = [&](double x, double y) {
    const double r = std::hypot(x, y);
    return -h - std::clamp((r - crest) * std::tan(25.0 * std::numbers::pi / 180.0), 0.0, drop);
  };
  const SensorModel vlp = SensorModel::vlp16();
  const std::vector<Box> boxes = {{{30.0, -1.0, -h - drop}, {31.0, 1.0, -h - drop + 1.0}}};
  const PointCloud cloud = synthetic_scan(vlp, ground, boxes, true, 0.01);
  const GroundScore with = score_synthetic(cloud, ground_robust(cloud, vlp));
  RobustGroundConfig no_descent;
  no_descent.descent_gap_m = std::numeric_limits<double>::infinity();
  const GroundScore without = score_synthetic(cloud, ground_robust(cloud, vlp, no_descent));
  std::printf("behind a crest: F1 %.4f FN %zu FP %zu (without the descent: F1 %.4f FN %zu)\n",
              with.f1, std::size_t(with.false_negative), std::size_t(with.false_positive),
              without.f1, std::size_t(without.false_negative));
  // Measured: every return right (the box too); without the descent the -9 deg ring's 1800
  // returns on the valley floor are lost (F1 0.923).
  EXPECT_EQ(with.false_negative, 0u);
  EXPECT_GE(without.false_negative, 1500u);
  EXPECT_LE(with.false_positive, without.false_positive);
  EXPECT_GT(with.f1, 0.999);
}

TEST(Ground, LitterUnderLowFoliageIsNotGroundOnADenseSensor) {
  // An OS1-64 1.2 m above flat ground. 5.5-6.5 m out, a patch of leaf litter 8 cm deep under
  // the low crown of a shrub: 4 cm leaves every 12 cm, 0.25-0.55 m above the litter, through
  // which the beams reach the litter. Behind the sensor, a hedge cut 5 cm above the ground.
  const double h = 1.2, litter = 0.08;
  const auto in_patch = [](double x, double y) { return x > 5.5 && x < 6.5 && std::abs(y) < 0.5; };
  auto ground = [&](double x, double y) { return -h + (in_patch(x, y) ? litter : 0.0); };
  std::vector<Box> boxes;
  for (double x = 5.56; x < 6.5; x += 0.12)
    for (double y = -0.44; y < 0.5; y += 0.12)
      for (double z = 0.25; z < 0.6; z += 0.1)
        boxes.push_back({{x - 0.02, y - 0.02, -h + litter + z - 0.02},
                         {x + 0.02, y + 0.02, -h + litter + z + 0.02}});
  boxes.push_back({{-7.0, -1.0, -h + 0.05}, {-5.0, 1.0, -h + 0.8}});
  SensorModel os = SensorModel::os1_64();
  const PointCloud cloud = synthetic_scan(os, ground, boxes, true, 0.005);
  RobustGroundConfig off;
  off.under_veg_min_returns = 0;
  const GroundResult with = ground_robust(cloud, os), without = ground_robust(cloud, os, off);
  std::size_t litter_n = 0, litter_kept = 0, litter_kept_before = 0, other_lost = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud.labels[i] != 1) continue;
    const Point& p = cloud.points[i];
    if (in_patch(p.x, p.y) && p.z > -h + 0.05) {
      ++litter_n;
      litter_kept += with.is_ground[i];
      litter_kept_before += without.is_ground[i];
    } else {
      other_lost += without.is_ground[i] && !with.is_ground[i];
    }
  }
  std::printf(
      "litter: %zu returns, %zu taken for ground (%zu without the test); other ground "
      "lost %zu\n",
      litter_n, litter_kept, litter_kept_before, other_lost);
  // Measured: 81 litter returns, all taken for ground by the plane tests alone, 23 with the
  // undergrowth test (it only looks at returns on or above their polar cell's plane, for speed:
  // where the litter fills a cell, the plane runs through it); no other ground return lost (the
  // hedge's foot included).
  ASSERT_GT(litter_n, 50u);
  EXPECT_GT(litter_kept_before, litter_n * 9 / 10);
  EXPECT_LT(litter_kept, litter_n / 3);
  EXPECT_EQ(other_lost, 0u);
}

TEST(Ground, InvalidPointsAreNeverGround) {
  SensorModel vlp = SensorModel::vlp16();
  PointCloud cloud = synthetic_scan(
      vlp, [](double, double) { return -1.0; }, {}, true);
  cloud.points[10] = Point{};  // the all-zero no-return marker
  cloud.points[11].x = std::numeric_limits<float>::quiet_NaN();
  for (GroundMethod m : {GroundMethod::kRobust, GroundMethod::kSeed000, GroundMethod::kSeed002,
                         GroundMethod::kGrid}) {
    GroundConfig cfg;
    cfg.method = m;
    const GroundResult r = segment_ground(cloud, vlp, cfg);
    EXPECT_EQ(r.is_ground[10], 0);
    EXPECT_EQ(r.is_ground[11], 0);
  }
  // An empty cloud is fine.
  EXPECT_TRUE(segment_ground(PointCloud{}, vlp).is_ground.empty());
}

TEST(Ground, TiltedSensorIsLevelledFirst) {
  // A VLP-16 1.2 m over flat ground, pitched 30 deg on its mount: in its own frame the ground is
  // the plane z = x tan(30) - 1.2 / cos(30), and a post stands on it.
  const double h = 1.2, t = 30.0 * std::numbers::pi / 180.0;
  auto ground = [&](double x, double) { return x * std::tan(t) - h / std::cos(t); };
  const SensorModel vlp = SensorModel::vlp16();
  const std::vector<Box> boxes = {{{4.0, 2.0, ground(4.0, 0) - 0.5}, {4.3, 2.3, 3.0}}};
  const PointCloud cloud = synthetic_scan(vlp, ground, boxes, true, 0.01);
  const UpEstimate up = estimate_up(cloud);
  EXPECT_NEAR(up.tilt_deg, 30.0, 1.0);
  EXPECT_NEAR(up.sensor_height_m, h, 0.05);
  EXPECT_LT(up.up.x(), -0.45);  // the ground rises towards +x: up leans back, towards -x
  const GroundResult levelled = segment_ground(cloud, vlp);
  EXPECT_TRUE(levelled.levelled);
  EXPECT_NEAR(levelled.sensor_height_m, h, 0.05);
  GroundConfig off;
  off.levelling.enabled = false;
  const GroundScore with = score_synthetic(cloud, levelled);
  const GroundScore without = score_synthetic(cloud, segment_ground(cloud, vlp, off));
  std::printf("pitched 30 deg: F1 %.4f levelled, %.4f not\n", with.f1, without.f1);
  EXPECT_GT(with.f1, 0.98);
  EXPECT_LT(without.f1, with.f1 - 0.1);
  // A measured up direction (an IMU) does the same; one within the tolerance leaves the cloud as
  // it is.
  GroundConfig imu;
  imu.levelling.up = Eigen::Vector3d(-std::sin(t), 0, std::cos(t));
  EXPECT_GT(score_synthetic(cloud, segment_ground(cloud, vlp, imu)).f1, 0.98);
  imu.levelling.up = Eigen::Vector3d(0.05, 0, 1);
  const GroundResult small = segment_ground(cloud, vlp, imu);
  EXPECT_FALSE(small.levelled);
  EXPECT_EQ(small.is_ground, segment_ground(cloud, vlp, off).is_ground);
}

class RellisGround : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(fieldlidar::test::data_file("rellis3d/000001.label")))
      GTEST_SKIP() << "real data rellis3d/000001.bin/.label absent";
    cloud = test::read_bin(fieldlidar::test::data_file("rellis3d/000001.bin"));
    labels = test::read_label_file(fieldlidar::test::data_file("rellis3d/000001.label"));
    ASSERT_EQ(labels.size(), cloud.size());
    sensor = SensorModel::os1_64();
    sensor.columns = 2048;
  }
  GroundScore score(const GroundResult& r) const {
    return score_ground(cloud, r.is_ground, labels, rellis_ground_classes(),
                        rellis_ignored_classes());
  }
  PointCloud cloud;
  std::vector<std::uint32_t> labels;
  SensorModel sensor;
};

TEST_F(RellisGround, RobustBeatsPatchworkPlusPlus) {
  // Patchwork++ with its defaults: P 0.914, R 0.970, F1 0.942 on this frame; the target
  // is F1 >= 0.96. Measured: P 0.964, R 0.961, F1 0.963 (without the undergrowth test P 0.942,
  // R 0.971, F1 0.956: the litter under a low tree crown that the truth labels "tree"). The
  // recall stays under Patchwork++'s: tall grass 0.1-0.4 m high, and a 0.9 m concrete structure
  // the truth labels as ground, are not ground here.
  const GroundScore s = score(ground_robust(cloud, sensor));
  EXPECT_GE(s.f1, 0.96) << "P " << s.precision << " R " << s.recall;
  EXPECT_GE(s.precision, 0.96);
  EXPECT_GE(s.recall, 0.958);
  RobustGroundConfig no_undergrowth;
  no_undergrowth.under_veg_min_returns = 0;
  const GroundScore before = score(ground_robust(cloud, sensor, no_undergrowth));
  EXPECT_LT(before.f1, s.f1 - 0.004);
}

TEST_F(RellisGround, SeedMethodsScoreAsMeasured) {
  // Regression bounds just under the measured figures (see the closing note).
  const GroundScore s000 = score(ground_seed000(cloud, sensor));
  EXPECT_GE(s000.f1, 0.90) << "P " << s000.precision << " R " << s000.recall;
  const GroundScore s002 = score(ground_seed002(cloud, sensor));
  EXPECT_GE(s002.f1, 0.70) << "P " << s002.precision << " R " << s002.recall;
  EXPECT_GE(s002.precision, 0.99);  // H - h <= 5 cm is strict: what it takes is ground
}

}  // namespace
}  // namespace fieldlidar::segmentation
