// fieldlidar legs-train: the seed's "learned feature library". Estimates the leg bounds (delta_c,
// L_min, L_max, dist_max and the additions' bounds) from annotated 2D scans (ROS bags with a
// PoseArray of leg positions per scan) and scans without people, and writes the YAML config.

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "fieldlidar/people/leg_classifier.hpp"
#include "fieldlidar/people/leg_training.hpp"
#include "fieldlidar/people/scan_resample.hpp"
#include "fieldlidar/sim/lidar_simulator.hpp"
#include "fieldlidar/sim/scenes.hpp"
#include "support/option_checks.hpp"
#include "support/tracking_truth.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {

struct TrainOptions {
  std::vector<std::string> positive;
  std::vector<std::string> negative;
  std::string scan_topic = "/training_scan";
  std::string truth_topic = "/leg_cluster_positions";
  std::vector<std::string> negative_topics;
  std::string out;
  double match_radius_m = 0.15;
  double low_quantile = 0.02;
  double high_quantile = 0.98;
  int sim_frames = 0;
  std::string sensor = "vlp16";
  bool force = false;
  bool classifier = true;
  bool classifier_asked = false;  ///< --classifier given on the command line (not the default)
  int rounds = 200;
  std::vector<std::string> exclude_features;
  std::vector<std::string> people_bags;  ///< leg_tracker/Person annotated bags
  std::string people_topic = "/ground_truth_people_tracks";
  std::string people_scan_topic;          ///< "": the bag's only scan topic
  std::vector<std::size_t> people_scans;  ///< first, last scan used (0-based; empty: all)
  double person_radius_m = 0.4;
  people::SegmentAugmentationConfig augment;  // off: measured not to help (docs/people.md)
};

/// Simulated people: lawn sweeps from a still sensor with the operator and strollers walking.
/// An arc is a leg when most of its points carry a person label (the simulator's truth); leg
/// pairs are the two legs of each simulated person.
void collect_simulated(int frames, const SensorModel& model, std::vector<people::LabelledArc>& arcs,
                       std::vector<double>& pairs) {
  sim::LawnConfig lawn;
  lawn.extra_walkers = 3;
  const auto scene = sim::make_lawn_scene(lawn, 7);
  SensorModel sensor = model;
  sensor.mounting_height_m = scene.sensor_height_m();
  const sim::LidarSimulator lidar(scene, sensor);
  follow::FollowConfig cfg;
  const auto legs = follow::legs_for_sensor(cfg.legs, sensor);
  for (int k = 0; k < frames; ++k) {
    // The sensor stands at a few places along the near edge, looking along the lawn.
    const Eigen::Vector2d xy(1.0 + 4.0 * (k % 5), 1.0);
    const Pose T =
        make_pose(xy.x(), xy.y(), scene.ground_height_at(xy) + sensor.mounting_height_m, 0, 0, 0);
    const auto frame = lidar.scan(0.5 * k, T);
    const auto clusters = follow::leg_band_clusters(frame.cloud, sensor, cfg);
    for (const auto& arc : people::extract_ring_arcs(frame.cloud, clusters, legs)) {
      std::size_t person = 0;
      for (auto i : arc.indices)
        person += label_class(frame.cloud.labels[i]) == LabelClass::kPerson;
      arcs.push_back({arc.features, 2 * person > arc.indices.size(), true});
    }
    for (const auto& p : frame.people)
      if (p.points > 0) pairs.push_back((p.legs_m[0] - p.legs_m[1]).norm());
  }
}

constexpr double kFarFromLegM = 0.5;

/// Adds the arcs of every scan of `topic` in `bag`, labelled against `truth` (PoseArray i belongs
/// to scan i; empty truth = no people), and each scan's angular step to `steps` when given.
void collect(const std::string& bag, const std::string& topic,
             const std::vector<io::PoseArraySample>& truth, const people::LegDetectorConfig& base,
             double radius, std::vector<people::LabelledArc>& arcs, std::vector<double>& pairs,
             std::size_t& scans, people::SegmentSamples& samples, bool annotated,
             const people::SegmentAugmentationConfig& augment, std::vector<double>* steps) {
  io::SourceOptions so;
  so.topic = topic;
  auto src = io::FrameSource::open(bag, so);
  while (auto f = src->next()) {
    ++scans;
    const std::vector<Eigen::Vector2d> pts = people::scan_points_2d(f->cloud);
    if (steps)
      if (const double step = people::scan_step_rad(pts); step > 0) steps->push_back(step);
    std::vector<Eigen::Vector2d> legs;
    if (f->index < truth.size())
      for (const auto& pose : truth[f->index].poses)
        legs.emplace_back(pose.translation().x(), pose.translation().y());
    const auto a = people::label_arcs_2d(pts, legs, base, radius);
    arcs.insert(arcs.end(), a.begin(), a.end());
    // Classifier samples: segments matched to an annotation are legs. Annotated bags label legs
    // inside a region only (people walk outside it unannotated), so their other segments are not
    // used; the non-leg samples come from the people-free bags (every segment is one there).
    people::collect_segment_samples(pts, legs, base.range_min_m, base.range_max_m,
                                    base.segment_jump_m, radius, kFarFromLegM, samples,
                                    /*negatives=*/!annotated, augment);
    const auto d = people::leg_pair_distances(legs);
    pairs.insert(pairs.end(), d.begin(), d.end());
  }
  warn_source_losses(*src);
}

/// Leg samples from a bag annotated with persons (leg_tracker/Person, one position per person, as
/// the leg_tracker benchmarks annotate): in the annotated scans FIRST..LAST, a segment whose mean
/// lies within `o.person_radius_m` of a person is a leg (one leg, or both seen as one). Like the
/// leg-annotated bags, only legs: such bags annotate people in a region only.
void collect_people(const std::string& bag, const TrainOptions& o,
                    const people::LegDetectorConfig& base, people::SegmentSamples& samples,
                    std::size_t& scans) {
  const TrackingTruth truth = bag_person_truth(bag, o.people_scan_topic, o.people_topic);
  const std::size_t n = truth.persons.size();
  const std::size_t first = o.people_scans.empty() ? 0 : o.people_scans[0];
  const std::size_t last = o.people_scans.empty() ? n : o.people_scans[1] + 1;
  if (first >= last || last > n)
    throw Error(fmt::format("--people-scans {}:{}: expected FIRST <= LAST < {} (the scans of {})",
                            first, last - 1, n, bag));
  io::SourceOptions so;
  so.topic = truth.topic;
  auto src = io::FrameSource::open(bag, so);
  while (auto f = src->next()) {
    if (f->index < first || f->index >= last || truth.persons[f->index].empty()) continue;
    ++scans;
    std::vector<Eigen::Vector2d> persons;
    for (const auto& p : truth.persons[f->index]) persons.push_back(p.position_m);
    people::collect_segment_samples(people::scan_points_2d(f->cloud), persons, base.range_min_m,
                                    base.range_max_m, base.segment_jump_m, o.person_radius_m,
                                    kFarFromLegM, samples, /*negatives=*/false, o.augment);
  }
  warn_source_losses(*src);
}

/// A name of segment_feature_names(); any other fails while the command line is parsed, before
/// any bag is read (the classifier would refuse it only once trained on negatives).
CLI::Validator segment_feature() {
  return CLI::Validator(
      [](std::string& name) -> std::string {
        std::string known;
        for (const char* k : people::segment_feature_names()) {
          if (name == k) return {};
          known += (known.empty() ? "" : ", ") + std::string(k);
        }
        return "'" + name + "' is not a segment feature (" + known + ")";
      },
      "");
}

void run_train(const TrainOptions& o) {
  namespace fs = std::filesystem;
  require(o.low_quantile < o.high_quantile, "--low-quantile",
          fmt::format("{} must be below --high-quantile {}", o.low_quantile, o.high_quantile));
  const fs::path out(o.out);
  std::vector<fs::path> inputs(o.positive.begin(), o.positive.end());
  inputs.insert(inputs.end(), o.negative.begin(), o.negative.end());
  io::check_writable(out, o.force, inputs);
  if (o.positive.empty() && o.sim_frames <= 0)
    throw Error("legs-train: give --positive bags (2D) or --sim-frames N (3D)");
  if (!o.positive.empty() && o.sim_frames > 0)
    throw Error(
        "legs-train: --positive (2D scans) and --sim-frames (3D sweeps) train different "
        "configs; give one of them");
  const bool sim3d = o.sim_frames > 0;
  require(o.people_bags.empty() || (!sim3d && o.classifier && !o.negative.empty()), "--people",
          "the persons' legs only train the 2D leg classifier: give --positive and --negative "
          "bags too (and not --no-classifier)");
  require(sim3d || !o.classifier_asked || !o.negative.empty(), "--classifier",
          "the leg classifier learns from scans without people too: give --negative bags (or "
          "--no-classifier for the config's bounds alone)");
  const people::LegDetectorConfig base = sim3d ? follow::FollowConfig::default_3d_legs()
                                               : people::seed_only(people::default_2d_legs());
  std::vector<people::LabelledArc> arcs;
  std::vector<double> pairs;
  people::SegmentSamples samples;
  std::size_t pos_scans = 0, neg_scans = 0;
  std::vector<double> steps;  // the positive scans' angular steps (rad)
  for (const auto& bag : o.positive)
    collect(bag, o.scan_topic, io::read_pose_arrays(bag, o.truth_topic), base, o.match_radius_m,
            arcs, pairs, pos_scans, samples, true, o.augment, &steps);
  std::size_t people_scans = 0;
  const std::size_t legs_before_people = samples.is_leg.size();
  for (const auto& bag : o.people_bags) collect_people(bag, o, base, samples, people_scans);
  const std::size_t people_legs = samples.is_leg.size() - legs_before_people;
  for (const auto& bag : o.negative) {
    std::vector<std::string> topics = o.negative_topics;
    if (topics.empty())
      for (const auto& t : io::bag_topics(bag))
        if (t.datatype == "sensor_msgs/LaserScan") topics.push_back(t.name);
    for (const auto& t : topics)
      collect(bag, t, {}, base, o.match_radius_m, arcs, pairs, neg_scans, samples, false, o.augment,
              nullptr);
  }
  if (sim3d) {
    const auto model = SensorModel::preset(o.sensor);
    if (!model) throw Error("--sensor '" + o.sensor + "': unknown sensor preset");
    collect_simulated(o.sim_frames, *model, arcs, pairs);
    pos_scans = std::size_t(o.sim_frames);
  }
  people::TrainingOptions opt;
  opt.low_quantile = o.low_quantile;
  opt.high_quantile = o.high_quantile;
  const auto r = people::estimate_leg_bounds(arcs, pairs, base, opt);
  auto c = r.config;
  // The additions measured to help on real scans are switched on in the written config.
  if (sim3d) {
    c.use_chord_max = true;  // the additions used by the follow pipeline's 3D config
  } else {
    c.use_min_points = c.use_chord_max = c.use_circle_fit = c.use_curve_min = c.use_background =
        true;
  }
  // 2D: the learned classifier (Real AdaBoost on segment features), written next to the config.
  std::string model_yaml;
  fs::path model_path;
  std::size_t model_legs = 0;
  if (!sim3d && o.classifier && o.negative.empty())
    fmt::print(
        "legs-train: no --negative bags: the leg classifier needs scans without people, it is "
        "not trained (the config uses the bounds)\n");
  if (!sim3d && o.classifier && !o.negative.empty()) {
    model_legs = std::size_t(std::count(samples.is_leg.begin(), samples.is_leg.end(), char(1)));
    if (model_legs == 0 || model_legs == samples.is_leg.size())
      throw Error("legs-train: the classifier needs leg and other segments; got " +
                  std::to_string(model_legs) + " legs of " + std::to_string(samples.is_leg.size()) +
                  " segments");
    people::BoostOptions bo;
    bo.rounds = o.rounds;
    bo.excluded_features = o.exclude_features;
    auto model = people::train_leg_classifier(samples.features, samples.is_leg, bo);
    // The step of the scans whose legs it learned: the pipeline resamples coarser scans to it.
    if (!steps.empty()) {
      std::nth_element(steps.begin(), steps.begin() + std::ptrdiff_t(steps.size() / 2),
                       steps.end());
      model.scan_step_rad = steps[steps.size() / 2];
    }
    model_path = out.parent_path() / (out.stem().string() + "_classifier.yaml");
    io::check_writable(model_path, o.force);
    const auto& a = o.augment;
    model_yaml =
        fmt::format("# trained by fieldlidar legs-train on {} leg and {} other segments\n",
                    model_legs, samples.is_leg.size() - model_legs) +
        (people_legs > 0 ? fmt::format("# ({} of the legs from {} person-annotated scans)\n",
                                       people_legs, people_scans)
                         : std::string()) +
        (a.copies > 0 ? fmt::format("# ({} re-seen copies per segment: range x {:g}..{:g}, width x "
                                    "{:g}..{:g}, range noise {:g} m)\n",
                                    a.copies, a.range_factor_min, a.range_factor_max,
                                    a.width_factor_min, a.width_factor_max, a.range_noise_m)
                      : std::string()) +
        people::to_yaml(model);
    c.classifier_file = model_path.filename().string();
  }
  const std::string yaml =
      fmt::format(
          "# estimated by fieldlidar legs-train from {} labelled and {} people-free scans\n"
          "# ({} leg arcs, {} other arcs, {} leg pairs; quantiles {:.3f}/{:.3f})\n",
          pos_scans, neg_scans, r.leg_arcs, r.other_arcs, r.leg_pairs, o.low_quantile,
          o.high_quantile) +
      people::to_yaml(c);
  if (!model_yaml.empty())
    io::write_file_atomic(model_path, model_yaml.data(), model_yaml.size(), o.force);
  io::write_file_atomic(out, yaml.data(), yaml.size(), o.force);
  if (!model_yaml.empty())
    fmt::print("legs-train: leg classifier from {} leg and {} other segments: wrote {}\n",
               model_legs, samples.is_leg.size() - model_legs, model_path.string());
  fmt::print(
      "legs-train: {} leg arcs, {} other arcs from {} + {} scans\n"
      "  delta_c {:.3f}, L_min {:.3f} m, L_max {:.3f} m, dist_max {:.3f} m\n"
      "  leg arcs accepted: seed bounds {:.3f}, with additions {:.3f}\n"
      "  other arcs accepted: seed bounds {:.3f}, with additions {:.3f}\nwrote {}\n",
      r.leg_arcs, r.other_arcs, pos_scans, neg_scans, c.curve_max, c.path_min_m, c.path_max_m,
      c.pair_distance_max_m, r.leg_accepted_seed, r.leg_accepted_all, r.other_accepted_seed,
      r.other_accepted_all, out.string());
}

}  // namespace

void add_legs_train_command(CLI::App& app) {
  auto o = std::make_shared<TrainOptions>();
  auto* cmd = app.add_subcommand(
      "legs-train", "Estimate the leg detector's bounds from annotated scans, write its YAML");
  cmd->add_option("--positive", o->positive, "Bags with scans and annotated legs (2D)");
  cmd->add_option("--sim-frames", o->sim_frames,
                  "Train a 3D config from this many simulated sweeps of walking people instead")
      ->check(whole_in(1, 100000));
  cmd->add_option("--sensor", o->sensor, "Sensor preset for --sim-frames")->capture_default_str();
  cmd->add_option("--negative", o->negative, "Bags of scans without people");
  auto* people_opt =
      cmd->add_option("--people", o->people_bags,
                      "2D classifier: more legs from bags with leg_tracker/Person annotations (a "
                      "site's own recordings, annotated as for eval-tracking): segments near an "
                      "annotated person are legs");
  cmd->add_option("--people-topic", o->people_topic, "Person annotation topic of --people bags")
      ->capture_default_str()
      ->needs(people_opt);
  cmd->add_option("--people-scan-topic", o->people_scan_topic,
                  "Scan topic of --people bags (default: the only scan topic)")
      ->needs(people_opt);
  cmd->add_option("--people-scans", o->people_scans,
                  "Use only scans FIRST..LAST of --people bags (0-based, inclusive), e.g. to keep "
                  "the rest for eval-tracking --scans")
      ->expected(2)
      ->needs(people_opt);
  cmd->add_option("--person-radius", o->person_radius_m,
                  "A segment whose mean is within this of an annotated person is a leg (m)")
      ->capture_default_str()
      ->check(real_above(0, 1))
      ->needs(people_opt);
  cmd->add_option("--scan-topic", o->scan_topic, "Scan topic of the positive bags")
      ->capture_default_str();
  cmd->add_option("--truth-topic", o->truth_topic, "PoseArray topic of the annotated legs")
      ->capture_default_str();
  cmd->add_option("--negative-topic", o->negative_topics,
                  "Scan topics of the negative bags (default: every LaserScan topic)");
  cmd->add_option("--match-radius", o->match_radius_m, "Arc-to-annotation match distance (m)")
      ->capture_default_str()
      ->check(real_above(0, 5));
  cmd->add_option("--low-quantile", o->low_quantile,
                  "Quantile of the leg features taken as each test's lower bound (below "
                  "--high-quantile)")
      ->capture_default_str()
      ->check(real_in(0, 1));
  cmd->add_option("--high-quantile", o->high_quantile,
                  "Quantile of the leg features taken as each test's upper bound")
      ->capture_default_str()
      ->check(real_in(0, 1));
  cmd->add_option("--out", o->out, "YAML config to write")->required();
  cmd->add_flag("--force", o->force, "Overwrite the output file");
  auto* classifier =
      cmd->add_flag("--classifier,!--no-classifier", o->classifier,
                    "2D: also train the learned leg classifier (written as OUT_classifier.yaml)")
          ->capture_default_str();
  cmd->add_option("--rounds", o->rounds, "Boosting rounds of the leg classifier")
      ->capture_default_str()
      ->check(whole_in(1, 5000));
  cmd->add_option("--exclude-features", o->exclude_features,
                  "2D classifier: features no tree may split on (names as in the classifier YAML, "
                  "e.g. range_m points angular_width_rad spacing_m: the range-dependent ones)")
      ->check(segment_feature());
  cmd->add_option("--augment", o->augment.copies,
                  "2D classifier: copies of each training segment re-seen farther and narrower "
                  "(0: none)")
      ->capture_default_str()
      ->check(whole_in(0, 20));
  cmd->add_option("--augment-range", o->augment.range_factor_max,
                  "Largest factor on a copy's range (drawn log-uniformly from 1)")
      ->capture_default_str()
      ->check(real_in(1, 10));
  cmd->add_option("--augment-max-range", o->augment.range_max_m,
                  "Copies whose centroid lands farther than this are dropped (m)")
      ->capture_default_str()
      ->check(real_above(0, 100));
  cmd->add_option("--augment-width", o->augment.width_factor_min,
                  "Smallest factor on a copy's cross-range width (drawn uniformly up to 0.9)")
      ->capture_default_str()
      ->check(real_in(0.1, 0.9));
  cmd->add_option("--augment-noise", o->augment.range_noise_m,
                  "Range noise added to a copy's returns (m)")
      ->capture_default_str()
      ->check(real_in(0, 0.1));
  cmd->callback([o, classifier] {
    o->classifier_asked = o->classifier && classifier->count() > 0;
    run_train(*o);
  });
}

}  // namespace fieldlidar::app
