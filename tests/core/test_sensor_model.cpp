#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "fieldlidar/core/sensor_model.hpp"

using namespace fieldlidar;

namespace {
double deg(double rad) {
  return rad * 180.0 / std::numbers::pi;
}
}  // namespace

TEST(SensorModel, PresetBeamTablesMatchDataSheets) {
  const auto vlp = SensorModel::vlp16();
  ASSERT_EQ(vlp.rings(), 16u);
  EXPECT_NEAR(deg(vlp.min_altitude_rad()), -15.0, 1e-9);
  EXPECT_NEAR(deg(vlp.max_altitude_rad()), 15.0, 1e-9);
  EXPECT_NEAR(deg(vlp.vertical_resolution_rad()), 2.0, 1e-9);
  EXPECT_NEAR(deg(vlp.horizontal_resolution_rad()), 0.2, 1e-9);

  const auto hdl64 = SensorModel::hdl64e();
  ASSERT_EQ(hdl64.rings(), 64u);
  EXPECT_NEAR(deg(hdl64.min_altitude_rad()), -24.33, 1e-6);
  EXPECT_NEAR(deg(hdl64.max_altitude_rad()), 2.0, 1e-6);
  EXPECT_EQ(SensorModel::hdl32e().rings(), 32u);
  EXPECT_EQ(SensorModel::vlp32c().rings(), 32u);
  EXPECT_NEAR(deg(SensorModel::vlp32c().min_altitude_rad()), -25.0, 1e-9);
  EXPECT_EQ(SensorModel::os1_64().rings(), 64u);
  EXPECT_EQ(SensorModel::os1_128().rings(), 128u);
  EXPECT_NEAR(deg(SensorModel::os1_128().max_altitude_rad()), 22.5, 1e-9);
  for (const auto& name : SensorModel::preset_names()) {
    auto m = SensorModel::preset(name);
    ASSERT_TRUE(m.has_value()) << name;
    EXPECT_NO_THROW(m->validate()) << name;
  }
  EXPECT_FALSE(SensorModel::preset("no-such-lidar").has_value());
}

TEST(SensorModel, NearestRingOnNonUniformTable) {
  const auto m = SensorModel::hdl64e();
  for (std::size_t r = 0; r < m.rings(); ++r)
    EXPECT_EQ(m.nearest_ring(m.beam_altitudes_rad[r] + 1e-5), r);
  EXPECT_EQ(m.nearest_ring(-1.0), 0u);
  EXPECT_EQ(m.nearest_ring(1.0), 63u);
}

TEST(SensorModel, ValidateNamesTheBadField) {
  auto m = SensorModel::vlp16();
  m.columns = 0;
  try {
    m.validate();
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("columns"), std::string::npos);
  }
  EXPECT_THROW(SensorModel::from_beam_angles("x", {}, 100), std::invalid_argument);
  EXPECT_THROW(SensorModel::from_beam_angles("x", {0.1, std::nan("")}, 100), std::invalid_argument);
}
