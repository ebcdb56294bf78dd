#pragma once
/// \file All core types.
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/grid2d.hpp"
#include "fieldlidar/core/labels.hpp"
#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/pose.hpp"
#include "fieldlidar/core/sensor_model.hpp"
