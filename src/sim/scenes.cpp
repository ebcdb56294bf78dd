#include "fieldlidar/sim/scenes.hpp"

#include <stdexcept>

namespace fieldlidar::sim {

Scene make_scene(SceneKind kind, std::uint64_t seed) {
  switch (kind) {
    case SceneKind::kLawn:
      return make_lawn_scene({}, seed);
    case SceneKind::kGreenhouse:
      return make_greenhouse_scene({}, seed);
    case SceneKind::kForest:
      return make_forest_scene({}, seed);
    case SceneKind::kTerrain:
      return make_terrain_scene({}, seed);
    case SceneKind::kCustom:
      break;
  }
  throw std::invalid_argument("make_scene: no procedural scene of kind 'custom'");
}

}  // namespace fieldlidar::sim
