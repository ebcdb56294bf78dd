#pragma once
// The picture of where annotated persons are lost in the 2D legs pipeline (eval-tracking
// --losses-png): each scored person at its place in the sensor frame of its scan, coloured by the
// furthest step it reached.

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/people/person_loss.hpp"

namespace fieldlidar::app {

struct PlacedLoss {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();  ///< sensor frame of its scan
  people::PersonLoss loss = people::PersonLoss::kNoSegment;
};

/// Writes a top-down PNG of the sensor frame: the sensor at the origin (x ahead), the scored
/// bearing wedge when given (deg, min and max), range rings every metre and each person as a dot
/// coloured by its loss, with a legend counting each loss. Refuses to replace an existing file
/// unless `overwrite`.
void write_losses_picture(const std::filesystem::path& path, std::span<const PlacedLoss> persons,
                          const std::vector<double>& wedge_deg, const std::string& title,
                          bool overwrite);

}  // namespace fieldlidar::app
