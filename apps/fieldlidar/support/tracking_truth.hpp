#pragma once
// Annotated persons per frame for `fieldlidar eval-tracking`: from a bag's leg_tracker/Person
// annotations or a simulated folder's people.csv, and tracked persons from a `legs --out` CSV.

#include <filesystem>
#include <string>
#include <vector>

#include "fieldlidar/people/clear_mot.hpp"

namespace fieldlidar::app {

using PersonsPerFrame = std::vector<std::vector<people::IdentifiedPoint>>;

/// The annotated persons per frame, in the sensor frame of each frame.
struct TrackingTruth {
  PersonsPerFrame persons;
  std::vector<double> stamps_s;  ///< per frame
  std::string frames_input;      ///< what FrameSource opens for the frames
  std::string topic;             ///< bag: the scan topic
  bool bag = false;
};

/// A bag's leg_tracker/Person annotations of `person_topic`, paired with the scans of `scan_topic`
/// ("" = the bag's only scan topic) by bag order.
TrackingTruth bag_person_truth(const std::string& bag, const std::string& scan_topic,
                               const std::string& person_topic);
/// A simulated folder: people.csv (world frame) moved into each frame's lidar frame at the sweep
/// start (poses.txt, times.txt), frames read from pcd/ (they carry the rings). Persons hit by
/// fewer than `min_points` returns (people.csv `points`) are left out. A people.csv without a
/// row is an error: there is no one to score.
TrackingTruth simulated_person_truth(const std::filesystem::path& dir, double min_points);
/// The sensor preset a simulated folder names in its scene.json ("" when it names none).
std::string simulated_sensor(const std::filesystem::path& dir);
/// Person rows (stamp,kind,x,y,track_id) of a `legs --out` CSV, each put in the frame whose
/// stamp in `stamps_s` it carries (within 1 ms); a row matching no frame is an error.
PersonsPerFrame read_person_tracks_csv(const std::filesystem::path& csv,
                                       const std::vector<double>& stamps_s);

}  // namespace fieldlidar::app
