#pragma once
// Choosing the sensor model and ground method from command-line words.

#include <string>

#include <CLI/CLI.hpp>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/segmentation/ground.hpp"

namespace fieldlidar::app {

/// The named preset, or one guessed from the number of rings (no ring field: HDL-64E, as KITTI),
/// the guess said in a warning on stderr. Throws fieldlidar::Error naming --sensor or the input
/// when neither works.
SensorModel sensor_for(const PointCloud& cloud, const std::string& input,
                       const std::string& preset);

/// The preset names, comma-separated ("vlp16, vlp32c, ...").
std::string sensor_preset_list();

/// A --sensor value that names a preset; an unknown name fails as "--sensor: 'NAME' is not a
/// known sensor preset (vlp16, ...)" while the command line is parsed.
CLI::Validator sensor_preset();

/// "robust", "grid", "seed000" or "seed002"; throws fieldlidar::Error naming --method otherwise.
segmentation::GroundMethod ground_method(const std::string& name);

}  // namespace fieldlidar::app
