#include <cmath>

#include <gtest/gtest.h>

#include "fieldlidar/core/grid2d.hpp"

using namespace fieldlidar;

TEST(Grid2D, CellLookupMatchesGeometry) {
  const auto g = GridGeometry::covering({-1.0, -2.0}, {0.95, 1.95}, 0.1);
  EXPECT_EQ(g.width, 20);
  EXPECT_EQ(g.height, 40);
  const auto c = g.cell_of({-0.95, -1.95});
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(*c, Eigen::Vector2i(0, 0));
  EXPECT_FALSE(g.cell_of({-1.01, 0.0}).has_value());
  EXPECT_FALSE(g.cell_of({std::nan(""), 0.0}).has_value());
  const auto center = g.cell_center(3, 4);
  EXPECT_NEAR(center.x(), -0.65, 1e-12);
  EXPECT_NEAR(center.y(), -1.55, 1e-12);
}

TEST(Grid2D, LayersAreNamedAndChecked) {
  Grid2D grid(GridGeometry::covering({0, 0}, {0.99, 0.99}, 0.5));
  grid.add_layer("elevation", 0.f);
  grid.at("elevation", 1, 1) = 2.5f;
  EXPECT_FLOAT_EQ(*grid.value_at("elevation", {0.8, 0.8}), 2.5f);
  EXPECT_FALSE(grid.value_at("elevation", {5.0, 0.0}).has_value());
  EXPECT_THROW(grid.layer("slope"), std::out_of_range);
  EXPECT_THROW(GridGeometry::covering({0, 0}, {1, 1}, 0.0), std::invalid_argument);
}
