#pragma once
/// \file A learned leg classifier for 2D scan segments (seed 000, step 3: "compare with the leg
/// model learned into the feature library"). The seed's bounds on L_k and L_k / D_k alone cannot
/// tell legs from leg-shaped furniture; a boosted ensemble of decision stumps over a richer
/// feature vector per segment can. Trained by `fieldlidar legs-train`, saved as YAML next to the
/// legs config and applied by detect_legs_2d when LegDetectorConfig::classifier is set.

#include <array>
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/people/leg_augmentation.hpp"

namespace fieldlidar::people {

/// Number of features per segment (see segment_feature_names()).
inline constexpr std::size_t kSegmentFeatures = 17;
using SegmentFeatures = std::array<double, kSegmentFeatures>;

/// Names of the features, in order (for the YAML file and reports).
std::span<const char* const> segment_feature_names();

/// Features of the segment [begin, end) of `scan` (range-filtered points in beam order, sensor at
/// the origin, metres): point count, chord D_k, path length L_k, bend L_k / D_k, circle-fit radius
/// and rms residual, linearity, std dev about the centroid, mean point spacing, range of the
/// centroid, angular width, signed sagitta (positive when the middle bulges toward the sensor),
/// circle centre behind the arc, range difference to the scan neighbours before and after the
/// segment (positive when the neighbour is farther), gap to the neighbours. Every value is finite
/// (unbounded ones are clamped).
SegmentFeatures segment_features(std::span<const Eigen::Vector2d> scan, std::size_t begin,
                                 std::size_t end);

/// One decision stump: `below` when feature <= threshold, `above` otherwise.
struct Stump {
  int feature = 0;
  double threshold = 0;
  double below = 0, above = 0;
  double eval(const SegmentFeatures& f) const {
    return f[std::size_t(feature)] <= threshold ? below : above;
  }
};

/// One weak learner of the Real AdaBoost ensemble: a depth-2 tree (a split, then a stump on each
/// side; with depth 1 both sides are constant stumps).
struct BoostTree {
  int feature = 0;
  double threshold = 0;
  Stump below, above;
  double eval(const SegmentFeatures& f) const {
    return f[std::size_t(feature)] <= threshold ? below.eval(f) : above.eval(f);
  }
};

struct LegClassifier {
  std::vector<BoostTree> trees;
  double threshold = 0.0;  ///< a segment is a leg when score() > threshold
  /// LegPipeline2D's rule for legs on occupied space (LegPipeline2DConfig::
  /// occupied_leg_score_min / occupied_leg_evidence_min), kept with the classifier because the
  /// score margin is in this classifier's score units: a classifier trained on other data scores
  /// differently. -inf / -inf (what legs-train writes): no such rule.
  double occupied_score_min = -std::numeric_limits<double>::infinity();
  double occupied_evidence_min = -std::numeric_limits<double>::infinity();
  /// The angular step of the scans it was trained on (rad; 0: unknown): its point-count, spacing
  /// and width features are that laser's, so LegPipeline2D resamples a coarser laser's scans to
  /// it (LegPipeline2DConfig::resample_min_ratio). YAML key scan_step_deg.
  double scan_step_rad = 0.0;
  double score(const SegmentFeatures& f) const;
  bool is_leg(const SegmentFeatures& f) const { return score(f) > threshold; }
};

/// Defaults measured on ../shared/data/legs_2d held out (leave one bag / one scan topic out, see
/// tests/people/test_legs_classifier_real.cpp): stumps generalised across bags better than
/// depth-2 trees (held-out leg recall 0.92 vs 0.69 at equal precision); the threshold -1.25 trades
/// per-scan precision for recall, the tracking of LegPipeline2D takes the rest of the clutter.
struct BoostOptions {
  int rounds = 200;  ///< trees in the ensemble
  int depth = 1;     ///< 1 = decision stumps, 2 = depth-2 trees
  int bins = 64;     ///< candidate thresholds per feature (quantiles of the training data)
  /// Total weight of the positives at the start (the rest on the negatives); 0.5 balances the
  /// classes, smaller values favour precision over recall.
  double positive_weight = 0.5;
  double threshold = -1.25;  ///< written into the classifier: leg when score > threshold
  /// Features (segment_feature_names()) no tree may split on, e.g. the range-dependent ones
  /// ("range_m", "points", "angular_width_rad", "spacing_m") for a classifier meant to judge legs
  /// farther than its training legs stood. Unknown names raise fieldlidar::Error.
  std::vector<std::string> excluded_features;
};

/// Real AdaBoost (Schapire and Singer) on greedy depth-1 or depth-2 trees. Throws
/// std::invalid_argument when a class is empty or sizes differ.
LegClassifier train_leg_classifier(std::span<const SegmentFeatures> features,
                                   std::span<const char> is_leg, const BoostOptions& options = {});

/// Training samples of one 2D scan: the segments detect_legs_2d would test (range filter, jump
/// split), positives those whose mean is within `match_radius_m` of an annotated leg, negatives
/// those farther than `far_radius_m` from every annotated leg; the ones in between are left out.
/// With `negatives` false only the positives are kept: scans annotated inside a region only
/// (e.g. every cluster within a wedge in front of the sensor) hold unannotated people outside it,
/// so their other segments are not known to be non-legs; negatives then come from people-free
/// scans. With `augmentation.copies` > 0, each kept segment also adds that many copies re-seen
/// farther and narrower (reseen_segment, leg_augmentation.hpp) with the same label.
struct SegmentSamples {
  std::vector<SegmentFeatures> features;
  std::vector<char> is_leg;
  void append(const SegmentSamples& o);
};
void collect_segment_samples(std::span<const Eigen::Vector2d> ordered_points,
                             std::span<const Eigen::Vector2d> truth_legs, double range_min_m,
                             double range_max_m, double segment_jump_m, double match_radius_m,
                             double far_radius_m, SegmentSamples& out, bool negatives = true,
                             const SegmentAugmentationConfig& augmentation = {});

/// YAML text of a classifier; parse it back with leg_classifier_from_yaml (throws
/// fieldlidar::Error naming `source` on malformed input or an unknown feature name).
std::string to_yaml(const LegClassifier& classifier);
LegClassifier leg_classifier_from_yaml(const std::string& text, const std::string& source);

}  // namespace fieldlidar::people
