// fieldlidar eval-people3d INPUT: the multi-ring (3D) leg and person detector of the follow
// pipeline (ground, leg-band clusters, leg arcs on several rings, pairs of legs) scored against
// annotated people in real sweeps: KITTI tracking boxes (Pedestrian, Cyclist) or SemanticKITTI
// point labels (a person class). Per annotated person: its points, leg-band points, legs and
// persons detected near it; recall of those with enough points, false persons elsewhere, time.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/rotate_points.hpp"
#include "fieldlidar/follow/pipeline.hpp"
#include "fieldlidar/follow/replay.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/frame_source.hpp"
#include "fieldlidar/io/kitti_calib.hpp"
#include "fieldlidar/io/kitti_tracking_labels.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "fieldlidar/people/leg_detector.hpp"
#include "support/option_checks.hpp"
#include "support/sensor_choice.hpp"
#include "support/sweep_levelling.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

struct People3dOptions {
  std::string input, kitti_labels, calib, point_labels, sensor, out;
  int person_class = 17;        ///< SemanticKITTI-format class of persons (RELLIS-3D: 17)
  std::size_t min_points = 50;  ///< persons with fewer points are reported, not scored
  double gate_m = 0.75;         ///< a person detection this near (x-y) finds the person
  double leg_radius_m = 0.6;    ///< legs this near the person's centre are "its" legs
  std::size_t max_frames = 0;   ///< 0 = all
  bool force = false;           ///< replace an existing --out file
  /// KITTI labels cover the left colour camera's view: |x| <= this * z in the rectified frame
  /// (image 1242 px wide, f = 721.5 px: +-40.7 deg).
  double camera_half_width = 621.0 / 721.5;
};

/// One annotated person (or cyclist) in one frame, with what the detector found near it.
struct Annotated {
  std::size_t frame = 0;
  int id = -1;
  std::string type;
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();  ///< lidar frame
  std::size_t points = 0, band_points = 0, legs_near = 0, persons_near = 0;
  double nearest_person_m = INFINITY;
};

nlohmann::json to_json(const Annotated& a) {
  return {{"frame", a.frame},
          {"id", a.id},
          {"type", a.type},
          {"x_m", a.center_m.x()},
          {"y_m", a.center_m.y()},
          {"range_m", a.center_m.head<2>().norm()},
          {"points", a.points},
          {"leg_band_points", a.band_points},
          {"legs_near", a.legs_near},
          {"persons_near", a.persons_near},
          {"nearest_person_m", std::isfinite(a.nearest_person_m) ? a.nearest_person_m : -1.0}};
}

void run(const People3dOptions& o) {
  const bool kitti = !o.kitti_labels.empty();
  if (kitti == !o.point_labels.empty())
    throw Error("eval-people3d: give --kitti-labels (with --calib) or --point-labels");
  std::vector<io::KittiObject> objects;
  io::KittiCalib calib;
  if (!o.out.empty()) io::check_writable(o.out, o.force, {o.input});
  if (kitti) {
    if (o.calib.empty()) throw Error("eval-people3d: --kitti-labels needs --calib");
    objects = io::read_kitti_tracking_labels(o.kitti_labels);
    calib = io::read_kitti_calib(o.calib);
  }
  const Pose T_velo_rect = calib.T_rect_velo.inverse();
  auto source = io::FrameSource::open(o.input);
  follow::FollowConfig cfg;
  std::vector<Annotated> people;
  nlohmann::json false_list = nlohmann::json::array();  ///< where the false persons stand
  std::size_t frames = 0, points = 0, detections = 0, false_persons = 0, legs_total = 0;
  std::size_t scored_detections = 0;
  std::size_t false_anywhere = 0;  ///< also where nothing is annotated (KITTI: outside the view)
                                   ///< ///< person detections where annotations exist
  double ms_total = 0, ms_max = 0;
  std::optional<SensorModel> sensor;
  bool level_warned = false;
  std::size_t levelled_frames = 0;
  while (auto frame = source->next()) {
    if (o.max_frames && frames >= o.max_frames) break;
    PointCloud& cloud = frame->cloud;
    points += cloud.valid_count();
    if (!sensor)
      sensor = source->sensor() ? *source->sensor() : sensor_for(cloud, o.input, o.sensor);
    // Leg arcs are found ring by ring: a cloud without a ring field (KITTI) gets estimated ones.
    follow::ensure_rings(cloud, *sensor);
    // A sweep tilted past the levelling's tolerance or turned over is levelled by its ground
    // plane first, as `legs` and the follow pipeline do; the annotations (in the sensor's frame)
    // are brought into the levelled one.
    const Pose T_level = levelling_pose(cloud, {}, o.input, nullptr, &level_warned);
    levelled_frames += T_level.linear() != Eigen::Matrix3d::Identity();
    rotate_points(cloud, T_level.linear().cast<float>());
    // Levelled frame -> the boxes' rectified camera frame, once per sweep.
    const Pose T_rect_level = calib.T_rect_velo * T_level.inverse();
    // The detector, as the follow pipeline runs it (perceive() without the world transform).
    const auto t0 = std::chrono::steady_clock::now();
    double h = 0;
    const auto clusters = follow::leg_band_clusters(cloud, *sensor, cfg, &h);
    const auto det = follow::detect_people_3d(cloud, clusters, *sensor, h, cfg, T_level.linear());
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ms_total += ms, ms_max = std::max(ms_max, ms);
    legs_total += det.legs.size();
    detections += det.people.size();

    // The annotated persons of this frame and their points.
    std::vector<Annotated> here;
    std::vector<const io::KittiObject*> boxes;
    std::vector<Eigen::Vector3d> sums;
    if (kitti) {
      for (const auto& ob : objects)
        if (ob.frame == int(frame->index) && (ob.type == "Pedestrian" || ob.type == "Cyclist") &&
            ob.has_box()) {
          boxes.push_back(&ob);
          Annotated a;
          a.frame = frame->index, a.id = ob.track_id, a.type = ob.type;
          a.center_m = T_level * (T_velo_rect * ob.center_rect_m());
          here.push_back(a);
        }
      for (const auto& p : cloud.points) {
        const Eigen::Vector3d q = T_rect_level * Eigen::Vector3d(p.x, p.y, p.z);
        for (std::size_t k = 0; k < boxes.size(); ++k)
          if (boxes[k]->contains(q)) {
            ++here[k].points;
            const double above = double(p.z) + h;
            here[k].band_points += above >= cfg.leg_height_min_m && above <= cfg.leg_height_max_m;
          }
      }
    } else {
      const auto labels = io::read_labels(o.point_labels, cloud.size());
      Annotated a;
      a.frame = frame->index, a.type = "person";
      for (std::size_t i = 0; i < cloud.size(); ++i) {
        if (int(labels[i] & 0xFFFF) != o.person_class) continue;
        const auto& p = cloud.points[i];
        a.center_m += Eigen::Vector3d(p.x, p.y, p.z);
        ++a.points;
        const double above = double(p.z) + h;
        a.band_points += above >= cfg.leg_height_min_m && above <= cfg.leg_height_max_m;
      }
      if (a.points) a.center_m /= double(a.points), here.push_back(a);
    }
    for (auto& a : here) {
      for (const auto& l : det.legs)
        a.legs_near += (l.position_m - a.center_m.head<2>()).norm() <= o.leg_radius_m;
      for (const auto& p : det.people) {
        const double d = (p.position_m - a.center_m.head<2>()).norm();
        a.nearest_person_m = std::min(a.nearest_person_m, d);
        a.persons_near += d <= o.gate_m;
      }
    }
    // Person detections near no annotated person (a pedestrian or the cyclist) are false; KITTI
    // annotates only what its camera sees, so there only detections in the camera's view count.
    for (const auto& p : det.people) {
      bool near_any = false;
      for (const auto& a : here)
        near_any |= (p.position_m - a.center_m.head<2>()).norm() <= o.gate_m;
      false_anywhere += !near_any;
      if (kitti) {
        const Eigen::Vector3d q =
            T_rect_level * Eigen::Vector3d(p.position_m.x(), p.position_m.y(), 0);
        if (!(q.z() > 0 && std::abs(q.x()) <= o.camera_half_width * q.z())) continue;
      }
      ++scored_detections;
      bool near = false;
      for (const auto& a : here) near |= (p.position_m - a.center_m.head<2>()).norm() <= o.gate_m;
      false_persons += !near;
      if (!near)
        false_list.push_back(
            {{"frame", frame->index}, {"x_m", p.position_m.x()}, {"y_m", p.position_m.y()}});
    }
    people.insert(people.end(), here.begin(), here.end());
    ++frames;
    fmt::print(stderr, "\rframe {}: {:.0f} ms, {} legs, {} persons   ", frame->index, ms,
               det.legs.size(), det.people.size());
  }
  fmt::print(stderr, "\n");
  if (!frames) throw Error(o.input + ": no frame");
  if (points == 0) throw Error(o.input + ": holds no points: no person to detect");
  // Recall over no one would read 0 (or 1), and every detection would be false: nothing to score.
  if (people.empty())
    throw Error(fmt::format(
        "eval-people3d: no annotated person in the {} frames scored ({})", frames,
        kitti ? "no Pedestrian or Cyclist box of " + o.kitti_labels + " in them"
              : fmt::format("no point of class {} in {}", o.person_class, o.point_labels)));

  // Recall per type over the persons with enough points.
  nlohmann::json by_type = nlohmann::json::object();
  for (const std::string type : {"Pedestrian", "Cyclist", "person"}) {
    std::size_t scored = 0, found = 0, legs_seen = 0, total = 0;
    for (const auto& a : people) {
      if (a.type != type) continue;
      ++total;
      if (a.points < o.min_points) continue;
      ++scored, found += a.persons_near > 0, legs_seen += a.legs_near > 0;
    }
    if (!total) continue;
    by_type[type] = {
        {"annotated", total},
        {"with_min_points", scored},
        {"found", found},
        {"recall", scored ? nlohmann::json(double(found) / double(scored)) : nlohmann::json()},
        {"with_a_leg_near", legs_seen}};
  }
  nlohmann::json j;
  j["input"] = o.input;
  j["sensor"] = sensor->name;
  j["frames"] = frames;
  j["levelled_frames"] = levelled_frames;
  j["min_points"] = o.min_points;
  j["gate_m"] = o.gate_m;
  j["legs_per_frame"] = double(legs_total) / double(frames);
  j["person_detections_per_frame"] = double(detections) / double(frames);
  j["person_detections_in_annotated_view"] = scored_detections;
  j["false_persons"] = false_persons;
  j["false_persons_per_frame"] = double(false_persons) / double(frames);
  j["false_person_detections"] = std::move(false_list);
  j["unmatched_persons_whole_sweep_per_frame"] = double(false_anywhere) / double(frames);
  j["annotated_view"] = kitti ? "KITTI camera view (+-40.7 deg)" : "whole sweep";
  j["by_type"] = by_type;
  j["mean_ms_per_frame"] = ms_total / double(frames);
  j["max_ms_per_frame"] = ms_max;
  j["people"] = nlohmann::json::array();
  for (const auto& a : people) j["people"].push_back(to_json(a));
  const std::string text = j.dump(2) + "\n";
  if (!o.out.empty()) io::write_file_atomic(o.out, text, o.force);
  fmt::print(
      "eval-people3d: {} frames ({}), {:.1f} legs and {:.2f} persons per frame, {:.2f} false "
      "persons per frame in the annotated view ({}), {:.0f} ms per frame (max {:.0f})\n",
      frames, sensor->name, double(legs_total) / double(frames),
      double(detections) / double(frames), double(false_persons) / double(frames),
      kitti ? "camera, +-40.7 deg" : "whole sweep", ms_total / double(frames), ms_max);
  for (const auto& [type, v] : by_type.items())
    fmt::print(
        "  {}: {} annotated, {} with >= {} points, {} found (recall {}), {} with a leg "
        "detected within {} m\n",
        type, v["annotated"].get<std::size_t>(), v["with_min_points"].get<std::size_t>(),
        o.min_points, v["found"].get<std::size_t>(),
        v["recall"].is_null() ? std::string("n/a")
                              : fmt::format("{:.2f}", v["recall"].get<double>()),
        v["with_a_leg_near"].get<std::size_t>(), o.leg_radius_m);
  if (!o.out.empty()) fmt::print("wrote {}\n", o.out);
}

}  // namespace

void add_eval_people3d_command(CLI::App& app) {
  auto o = std::make_shared<People3dOptions>();
  auto* cmd = app.add_subcommand(
      "eval-people3d",
      "Score the 3D (multi-ring) leg/person detector against annotated people in real sweeps");
  cmd->add_option("input", o->input, "Sweeps: a file, folder, glob, pcap or bag")->required();
  cmd->add_option("--kitti-labels", o->kitti_labels,
                  "KITTI tracking labels (Pedestrian and Cyclist boxes, frame = sweep index)");
  cmd->add_option("--calib", o->calib, "KITTI calib.txt (R0_rect, Tr_velo_to_cam) for the boxes");
  cmd->add_option("--point-labels", o->point_labels,
                  "SemanticKITTI-format .label of a single sweep (persons = --person-class)");
  // Label files keep the class in the low 16 bits (the instance above it).
  cmd->add_option("--person-class", o->person_class, "Person class id in --point-labels")
      ->capture_default_str()
      ->check(whole_in(0, 65535));
  cmd->add_option("--min-points", o->min_points, "Persons with fewer points are not scored")
      ->capture_default_str()
      ->check(whole_in(0, 1000000000));
  cmd->add_option("--gate", o->gate_m, "Match distance of a person detection (m, x-y)")
      ->capture_default_str()
      ->check(real_above(0));
  cmd->add_option("--max-frames", o->max_frames, "Stop after this many frames (0 = all)")
      ->check(whole_in(0, 1000000000));
  cmd->add_option("--sensor", o->sensor, "Sensor preset when the input does not say");
  cmd->add_option("--out", o->out,
                  "Write the figures as JSON here: per annotated person, and where each false "
                  "person detection stands (frame, x, y in the sensor frame)");
  cmd->add_flag("--force", o->force, "Replace an existing --out file");
  cmd->callback([o] { run(*o); });
}

}  // namespace fieldlidar::app
