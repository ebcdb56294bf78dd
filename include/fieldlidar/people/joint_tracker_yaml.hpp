#pragma once
/// \file The person tracker's settings (JointTrackerConfig) as YAML text: the `tracker:` map of a
/// leg detector file (`fieldlidar legs|eval-tracking|follow --replay --config FILE`), so that a
/// robot's people tracking is tuned for its laser and its site without a rebuild. Only text is
/// handled here: reading files is the caller's job.

#include <string>

#include "fieldlidar/people/joint_person_tracker.hpp"

namespace fieldlidar::people {

/// `tracker:` and every field, its unit in the comment.
std::string to_yaml(const JointTrackerConfig& config);

/// The `tracker:` map of `text` parsed onto `base` (absent keys, or no such map, keep their
/// value). Throws fieldlidar::Error naming `source` and the key for an unknown key, a bad or
/// non-finite value, or settings no tracker can run with (a gate, a noise or a speed not
/// positive, a decay outside (0, 1), a follow zone whose far range is not beyond its near one).
JointTrackerConfig joint_tracker_config_from_yaml(const std::string& text,
                                                  const std::string& source,
                                                  const JointTrackerConfig& base = {});

}  // namespace fieldlidar::people
