#pragma once
// Reflectivity of the scene's classes, for the simulated intensity channel.

#include <cstdint>

#include "fieldlidar/core/labels.hpp"

namespace fieldlidar::sim::detail {

/// Fraction of light returned at normal incidence per class (for the intensity channel).
inline double reflectivity(std::uint32_t label) {
  switch (label_class(label)) {
    case LabelClass::kGround:
      return 0.30;
    case LabelClass::kPerson:
      return 0.45;
    case LabelClass::kTrunk:
      return 0.35;
    case LabelClass::kVegetation:
      return 0.50;
    case LabelClass::kStructure:
      return 0.70;
    case LabelClass::kObstacle:
      return 0.25;
    default:
      return 0.30;
  }
}

}  // namespace fieldlidar::sim::detail
