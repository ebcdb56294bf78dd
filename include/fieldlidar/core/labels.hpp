#pragma once
/// \file Per-point label layout shared by the simulator, the segmenters and the evaluation tools.
///
/// A label is a uint32 in the SemanticKITTI layout: the low 16 bits are the class, the high 16 bits
/// an instance id (person id, trunk id, ...; 0 = none).

#include <cstdint>

namespace fieldlidar {

/// Classes used by fieldlidar's simulator and outputs.
enum class LabelClass : std::uint16_t {
  kUnlabelled = 0,  ///< no return / unknown
  kGround = 1,      ///< terrain, lawn, floor, road
  kPerson = 2,      ///< a person (legs, torso); instance = person id
  kTrunk = 3,       ///< a tree trunk; instance = tree id
  kVegetation = 4,  ///< canopy, branches, shrubs, hedges, plants
  kStructure = 5,   ///< buildings, sheds, walls, posts, benches, greenhouse frames
  kObstacle = 6,    ///< rocks and other solid objects on the ground
};

constexpr std::uint32_t make_label(LabelClass c, std::uint16_t instance = 0) {
  return static_cast<std::uint32_t>(c) | (static_cast<std::uint32_t>(instance) << 16);
}
constexpr LabelClass label_class(std::uint32_t label) {
  return static_cast<LabelClass>(label & 0xFFFFu);
}
constexpr std::uint16_t label_instance(std::uint32_t label) {
  return static_cast<std::uint16_t>(label >> 16);
}

}  // namespace fieldlidar
