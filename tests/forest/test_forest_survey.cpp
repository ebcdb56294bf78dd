// Any seed and sensor on demand, for looking at seeds no test asserts (not run by default):
//   FOREST_SEED=7 FOREST_SENSOR=os1|vlp16|tilting FOREST_FRAMES=10 FOREST_DEBUG=1 test_forest
//   --gtest_also_run_disabled_tests --gtest_filter=ForestSim.DISABLED_Survey
// with TreeConfig overrides FOREST_BRIDGED_RUNS, FOREST_MIN_TOP, FOREST_TOP_CLEAR and the score
// rule's FOREST_MIN_VISIBLE.
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "forest_eval.hpp"

namespace fieldlidar::forest::test {

TEST(ForestSim, DISABLED_Survey) {
  const char* seed = std::getenv("FOREST_SEED");
  const char* frames = std::getenv("FOREST_FRAMES");
  const std::string name = std::getenv("FOREST_SENSOR") ? std::getenv("FOREST_SENSOR") : "os1";
  const SensorModel sensor = name == "vlp16"     ? SensorModel::vlp16()
                             : name == "tilting" ? SensorModel::tilting_2d()
                                                 : SensorModel::os1_64();
  TreeConfig config;
  if (const char* b = std::getenv("FOREST_BRIDGED_RUNS"))
    config.segments.max_bridged_runs = std::size_t(std::atoi(b));
  if (const char* v = std::getenv("FOREST_MIN_TOP")) config.min_top_seen_m = std::atof(v);
  if (const char* v = std::getenv("FOREST_TOP_CLEAR")) config.top_clear_m = std::atof(v);
  ScoreRule rule;
  if (const char* v = std::getenv("FOREST_MIN_VISIBLE")) rule.min_visible = std::atof(v);
  const auto s = run_frames(seed ? std::atoi(seed) : 7, sensor, frames ? std::atoi(frames) : 10,
                            config, std::getenv("FOREST_DEBUG") != nullptr, rule);
  s.print((name + " seed " + (seed ? seed : "7")).c_str());
}

}  // namespace fieldlidar::forest::test
