#pragma once
// The annotated 2D leg scans of ../shared/data/legs_2d loaded for evaluation: each scan's points
// in beam order and its annotated legs (PoseArray i belongs to scan i).
//
// The annotations of positive_N_extracted.bag are every cluster (>= 3 points, 0.13 m) whose
// centre lies in a wedge in front of the laser: bearing -15..15 deg (-15..10 deg for bag 4) and
// range <= 5 m (the dataset's own extraction settings, leg_tracker's
// extract_positive_training_clusters_res=0.33.launch). Outside the wedge nothing is annotated,
// and the scans do hold other people walking there, so precision is scored inside the wedge:
// a detection outside it counts when it matches an annotated leg and is not scored otherwise.

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "test_data.hpp"

namespace fieldlidar::test {

struct LegScan {
  double stamp_s = 0;
  int bag = 0;  ///< positive_N_extracted.bag: N; 0 for people-free scans
  std::vector<Eigen::Vector2d> points;
  std::vector<Eigen::Vector2d> legs;  ///< annotated (empty for negative scans)
  bool first_of_bag = false;
};

/// True when `p` (sensor frame, m) is inside the annotated wedge of positive bag `bag`.
inline bool in_annotated_region(const Eigen::Vector2d& p, int bag) {
  return people::in_bearing_wedge(p, -15.0, bag == 4 ? 10.0 : 15.0, 5.0);
}

inline std::vector<LegScan> load_leg_scans(const std::string& bag, const std::string& topic,
                                           const std::string& truth_topic, int bag_number = 0) {
  std::vector<LegScan> scans;
  std::vector<io::PoseArraySample> truth;
  if (!truth_topic.empty()) truth = io::read_pose_arrays(data_file(bag), truth_topic);
  io::SourceOptions so;
  so.topic = topic;
  auto src = io::FrameSource::open(data_file(bag), so);
  while (auto f = src->next()) {
    LegScan s;
    s.stamp_s = f->stamp_s;
    s.bag = bag_number;
    s.points = people::scan_points_2d(f->cloud);
    if (f->index < truth.size())
      for (const auto& pose : truth[f->index].poses)
        s.legs.emplace_back(pose.translation().x(), pose.translation().y());
    s.first_of_bag = scans.empty();
    scans.push_back(std::move(s));
  }
  return scans;
}

inline std::vector<LegScan> positive_scans(std::initializer_list<int> bags = {1, 2, 3, 4}) {
  std::vector<LegScan> all;
  for (int b : bags) {
    auto s = load_leg_scans("legs_2d/positive_" + std::to_string(b) + "_extracted.bag",
                            "/training_scan", "/leg_cluster_positions", b);
    all.insert(all.end(), s.begin(), s.end());
  }
  return all;
}

inline std::vector<LegScan> negative_scans() {
  std::vector<LegScan> all;
  for (const char* t : {"/left_scan", "/rear_scan", "/right_scan"}) {
    auto s = load_leg_scans("legs_2d/negative_2.bag", t, "");
    all.insert(all.end(), s.begin(), s.end());
  }
  return all;
}

struct LegScores {
  people::MatchCounts legs;  ///< false positives counted inside the annotated region only
  double recall = 0, precision = 0;
  double precision_whole_scan = 0;  ///< every unmatched detection counted as false
  double false_persons_per_scan = 0;
};

/// Adds one scan's detections to `counts`: greedy nearest matching within `radius`; unmatched
/// detections are false positives when inside the scan's annotated region (or when `whole`).
inline void score_scan(std::span<const Eigen::Vector2d> detections, const LegScan& scan,
                       double radius, people::MatchCounts& counts, bool whole) {
  std::vector<char> matched;
  auto m = people::match_points(detections, scan.legs, radius, &matched);
  if (!whole && scan.bag > 0)
    for (std::size_t i = 0; i < detections.size(); ++i)
      if (!matched[i] && !in_annotated_region(detections[i], scan.bag)) --m.false_positive;
  counts += m;
}

/// Scans in order of `pos` form one sequence per bag; the background model restarts at each bag.
inline LegScores score_legs(const people::LegDetectorConfig& c, const std::vector<LegScan>& pos,
                            const std::vector<LegScan>& neg, double radius = 0.15) {
  LegScores s;
  people::MatchCounts whole;
  people::StaticBackground bg;
  for (const auto& scan : pos) {
    if (scan.first_of_bag) bg = people::StaticBackground();
    const auto d = people::detect_legs_2d(scan.points, c, &bg);
    bg.update(scan.points);
    std::vector<Eigen::Vector2d> legs;
    for (const auto& l : d.legs) legs.push_back(l.position_m);
    score_scan(legs, scan, radius, s.legs, false);
    score_scan(legs, scan, radius, whole, true);
  }
  std::size_t persons = 0;
  for (const auto& scan : neg) {
    if (scan.first_of_bag) bg = people::StaticBackground();
    persons += people::detect_legs_2d(scan.points, c, &bg).people.size();
    bg.update(scan.points);
  }
  s.recall = s.legs.recall();
  s.precision = s.legs.precision();
  s.precision_whole_scan = whole.precision();
  s.false_persons_per_scan = neg.empty() ? 0 : double(persons) / double(neg.size());
  return s;
}

inline people::TrainingResult train_legs(const std::vector<LegScan>& pos,
                                         const std::vector<LegScan>& neg,
                                         const people::LegDetectorConfig& base,
                                         const people::TrainingOptions& opt = {}) {
  std::vector<people::LabelledArc> arcs;
  std::vector<double> pairs;
  for (const auto& s : pos) {
    auto a = people::label_arcs_2d(s.points, s.legs, base, 0.15);
    arcs.insert(arcs.end(), a.begin(), a.end());
    auto p = people::leg_pair_distances(s.legs);
    pairs.insert(pairs.end(), p.begin(), p.end());
  }
  for (const auto& s : neg) {
    auto a = people::label_arcs_2d(s.points, {}, base, 0.15);
    arcs.insert(arcs.end(), a.begin(), a.end());
  }
  return people::estimate_leg_bounds(arcs, pairs, base, opt);
}

}  // namespace fieldlidar::test
