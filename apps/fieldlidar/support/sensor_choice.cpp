#include "support/sensor_choice.hpp"

#include <cstdio>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::app {

SensorModel sensor_for(const PointCloud& cloud, const std::string& input,
                       const std::string& preset) {
  if (!preset.empty()) {
    auto s = SensorModel::preset(preset);
    if (!s) throw Error("--sensor '" + preset + "' is not a known sensor preset");
    return *s;
  }
  if (cloud.fields.ring) {
    switch (cloud.ring_count()) {
      case 16:
        return SensorModel::vlp16();
      case 32:
        return SensorModel::hdl32e();
      case 64:
        return SensorModel::os1_64();
      case 128:
        return SensorModel::os1_128();
      default:
        break;
    }
    throw Error(input + ": " + std::to_string(cloud.ring_count()) +
                " rings match no preset; pass --sensor");
  }
  // A guess, said aloud: the robust ground's polar cells and face tests follow the sensor.
  fmt::print(stderr,
             "fieldlidar: warning: {}: no ring field; sensor assumed hdl64e (give --sensor)\n",
             input);
  return SensorModel::hdl64e();
}

segmentation::GroundMethod ground_method(const std::string& name) {
  if (name == "robust") return segmentation::GroundMethod::kRobust;
  if (name == "seed000") return segmentation::GroundMethod::kSeed000;
  if (name == "seed002") return segmentation::GroundMethod::kSeed002;
  if (name == "grid") return segmentation::GroundMethod::kGrid;
  throw Error("--method '" + name + "' is not robust, grid, seed000 or seed002");
}

}  // namespace fieldlidar::app
