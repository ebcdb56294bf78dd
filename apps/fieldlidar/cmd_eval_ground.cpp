// fieldlidar eval-ground INPUT LABELS_TRUTH: precision, recall and F1 of a ground segmentation
// against SemanticKITTI-format truth labels.

#include <cstdio>
#include <memory>
#include <string>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/sensor_model.hpp"
#include "fieldlidar/io/cloud_file.hpp"
#include "fieldlidar/io/label_file.hpp"
#include "fieldlidar/segmentation/segment.hpp"
#include "support/sensor_choice.hpp"
#include "support/warnings.hpp"

namespace fieldlidar::app {

namespace {
struct EvalOptions {
  std::string input, truth, method = "robust", classes = "semantickitti", sensor;
  bool json = false;
};

void run(const EvalOptions& o) {
  const PointCloud cloud = io::read_cloud(o.input);
  if (cloud.valid_count() == 0)
    throw Error(o.input + ": the scan has no valid point (" + std::to_string(cloud.size()) +
                " points): nothing to score");
  const std::vector<std::uint32_t> truth = io::read_labels(o.truth, cloud.size());
  std::vector<std::uint16_t> ground_classes, ignored;
  if (o.classes == "semantickitti") {
    ground_classes = segmentation::semantickitti_ground_classes();
    ignored = segmentation::semantickitti_ignored_classes();
  } else if (o.classes == "rellis") {
    ground_classes = segmentation::rellis_ground_classes();
    ignored = segmentation::rellis_ignored_classes();
  } else {
    throw Error("eval-ground: --classes '" + o.classes + "' is not semantickitti or rellis");
  }
  const SensorModel sensor = sensor_for(cloud, o.input, o.sensor);
  segmentation::GroundConfig cfg;
  cfg.method = ground_method(o.method);
  const segmentation::GroundResult r = segmentation::segment_ground(cloud, sensor, cfg);
  if (!r.up_found)
    warn(o.input +
         ": no ground plane below the sensor within 45 deg of its z axis, upright or "
         "turned over (a sensor tilted further?): segmented as if level");
  const segmentation::GroundScore s =
      segmentation::score_ground(cloud, r.is_ground, truth, ground_classes, ignored);
  if (s.true_positive + s.false_negative == 0)
    throw Error("eval-ground: no scored point of " + o.truth + " is ground under the " + o.classes +
                " class ids; are they " +
                (o.classes == "rellis" ? "SemanticKITTI ids (--classes semantickitti)?"
                                       : "RELLIS-3D ids (--classes rellis)?"));
  if (o.json) {
    nlohmann::json j;
    j["file"] = o.input;
    j["truth"] = o.truth;
    j["method"] = o.method;
    j["classes"] = o.classes;
    j["precision"] = s.precision;
    j["recall"] = s.recall;
    j["f1"] = s.f1;
    j["true_positive"] = s.true_positive;
    j["false_positive"] = s.false_positive;
    j["false_negative"] = s.false_negative;
    j["true_negative"] = s.true_negative;
    j["sensor_height_m"] = r.sensor_height_m;
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  fmt::print("method:     {} ({} classes, sensor {})\n", o.method, o.classes, sensor.name);
  fmt::print("scored:     {} points (TP {}, FP {}, FN {}, TN {})\n",
             s.true_positive + s.false_positive + s.false_negative + s.true_negative,
             s.true_positive, s.false_positive, s.false_negative, s.true_negative);
  fmt::print("precision:  {:.4f}\n", s.precision);
  fmt::print("recall:     {:.4f}\n", s.recall);
  fmt::print("F1:         {:.4f}\n", s.f1);
}

}  // namespace

void add_eval_ground_command(CLI::App& app) {
  auto opts = std::make_shared<EvalOptions>();
  auto* cmd = app.add_subcommand(
      "eval-ground", "Score a ground segmentation against SemanticKITTI-format truth labels");
  cmd->add_option("INPUT", opts->input, "Input scan (.bin, .pcd, ...)")->required();
  cmd->add_option("LABELS_TRUTH", opts->truth, "Truth labels (.label, uint32 per point)")
      ->required();
  cmd->add_option("--method", opts->method, "Ground method: robust, seed000, seed002")
      ->capture_default_str();
  cmd->add_option("--classes", opts->classes,
                  "Class ids of the truth: semantickitti (ground = road, parking, sidewalk, "
                  "other-ground, lane marking, terrain) or rellis (dirt, grass, asphalt, concrete, "
                  "puddle, mud); void/unlabelled points are not scored")
      ->capture_default_str();
  cmd->add_option("--sensor", opts->sensor, "Sensor preset; default from the rings");
  cmd->add_flag("--json", opts->json, "Print machine-readable JSON");
  cmd->callback([opts] { run(*opts); });
}

}  // namespace fieldlidar::app
