#include "support/sensor_choice.hpp"

#include <cstdio>
#include <optional>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::app {

std::string sensor_preset_list() {
  std::string list;
  for (const auto& name : SensorModel::preset_names()) list += (list.empty() ? "" : ", ") + name;
  return list;
}

CLI::Validator sensor_preset() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        if (SensorModel::preset(s)) return {};
        return "'" + s + "' is not a known sensor preset (" + sensor_preset_list() + ")";
      },
      "");
}

SensorModel sensor_for(const PointCloud& cloud, const std::string& input,
                       const std::string& preset) {
  if (!preset.empty()) {
    auto s = SensorModel::preset(preset);
    if (!s)
      throw Error("--sensor '" + preset + "' is not a known sensor preset (" +
                  sensor_preset_list() + ")");
    return *s;
  }
  if (cloud.fields.ring) {
    std::optional<SensorModel> guess;
    switch (cloud.ring_count()) {
      case 16:
        guess = SensorModel::vlp16();
        break;
      case 32:
        guess = SensorModel::hdl32e();
        break;
      case 64:
        guess = SensorModel::os1_64();
        break;
      case 128:
        guess = SensorModel::os1_128();
        break;
      default:
        throw Error(input + ": " + std::to_string(cloud.ring_count()) +
                    " rings match no preset; pass --sensor");
    }
    // Several sensors share a ring count (HDL-64E and OS1-64): the choice is said aloud.
    fmt::print(stderr,
               "fieldlidar: warning: {}: sensor taken as {} from its {} rings (give --sensor)\n",
               input, guess->name, cloud.ring_count());
    return *guess;
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
