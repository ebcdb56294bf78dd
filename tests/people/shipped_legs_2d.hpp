#pragma once
// The shipped 2D leg pipeline settings (config/legs_2d.yaml and its learned classifier), for
// tests built with FIELDLIDAR_CONFIG_DIR set to the source tree's config/.

#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "fieldlidar/people/leg_classifier.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "fieldlidar/people/legs_2d_pipeline.hpp"

namespace fieldlidar::test {

inline std::string read_config_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline people::LegPipeline2DConfig shipped_legs_2d() {
  const std::string dir = FIELDLIDAR_CONFIG_DIR;
  people::LegPipeline2DConfig c;
  c.detector = people::legs_config_from_yaml(read_config_text(dir + "/legs_2d.yaml"),
                                             "legs_2d.yaml", people::default_2d_legs());
  c.detector.classifier =
      std::make_shared<const people::LegClassifier>(people::leg_classifier_from_yaml(
          read_config_text(dir + "/" + c.detector.classifier_file), c.detector.classifier_file));
  return c;
}

}  // namespace fieldlidar::test
