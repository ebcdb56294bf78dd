// fieldlidar eval-tracking end to end: CLEAR MOT of the legs pipeline on the leg_tracker
// benchmark bag (annotations paired with scans by bag order, the benchmark's bearing wedge), the
// same figures from a `legs --out` CSV, a simulated folder's people.csv, and its refusals.

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_cli.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

namespace fs = std::filesystem;

constexpr const char* kBag = "legs_2d_tracking/general_tracking_moving_1.bag";

/// Runs `fieldlidar eval-tracking ARGS --json` and parses what it printed.
nlohmann::json eval_json(const std::string& args) {
  const auto r = test::run_cli("eval-tracking " + args + " --json");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  if (r.exit_code != 0) return {};
  return nlohmann::json::parse(r.output);
}

TEST(CliEvalTracking, BenchmarkBagScoresItsWedgeWithTheLegsPipeline) {
  FIELDLIDAR_REQUIRE_DATA(kBag);
  const auto bag = test::quoted(test::data_file(kBag));
  const auto j = eval_json(bag);
  ASSERT_FALSE(j.is_null());
  // 873 scans; 153 leg_tracker/Person annotations, 133 of them at bearings -80..12 deg (the
  // benchmark's scorer counts those), in 109 scans.
  EXPECT_EQ(j["frames"], 873);
  EXPECT_EQ(j["annotated_persons"], 153);
  EXPECT_EQ(j["truth_scored"], 133);
  EXPECT_EQ(j["frames_with_truth"], 109);
  EXPECT_EQ(j["truth_wedge_deg"], nlohmann::json({-80.0, 12.0}));
  EXPECT_EQ(j["gate_m"], 0.75);
  const int truth = j["truth_scored"], matches = j["matches"], misses = j["misses"];
  const int fp = j["false_positives"], ids = j["id_switches"];
  EXPECT_EQ(matches + misses, truth);
  EXPECT_NEAR(double(j["mota"]), 1.0 - double(misses + fp + ids) / truth, 1e-12);
  // Measured with the shipped settings: 43 of 133 matched, 15 false persons (7 on scans 0-436,
  // 8 on 437-872), MOTA 0.211 over the whole bag, no id switch (2 matched and 1 false person
  // before leg-sized blobs the classifier cannot judge were kept out of the person grid). The
  // issue's targets (MOTA >= 0.40, recall >= 0.60) are not reached.
  EXPECT_GE(matches, 43);
  EXPECT_LE(fp, 16);
  EXPECT_GE(double(j["mota"]), 0.2);
  EXPECT_EQ(ids, 0);
  // Leg-sized returns kept out of the occupancy grid: 39 of 133 matched, MOTA 0.165 over the
  // whole bag (8 false persons on scans 0-436, 9 on 437-872), MOTP 0.106 m, no id switch; since
  // walking legs stay out of the fast grids, 45 matched, 22 false persons (0.0252 per scan).
  const auto kept = eval_json(bag + " --compact-occupancy 0");
  ASSERT_FALSE(kept.is_null());
  EXPECT_GE(int(kept["matches"]), 37);
  EXPECT_GE(double(kept["mota"]), 0.15);
  EXPECT_LT(double(kept["motp_m"]), 0.12);
  EXPECT_LE(double(kept["false_positives_per_frame"]), 0.028);
  EXPECT_EQ(int(kept["id_switches"]), 0);

  // --scans scores a range of frames (the tracker still runs on all): every scored annotation
  // lies in scans 0..436; the tracker's settings were chosen there.
  const auto first = eval_json(bag + " --scans 0:436");
  const auto second = eval_json(bag + " --scans 437:872");
  ASSERT_FALSE(first.is_null());
  ASSERT_FALSE(second.is_null());
  EXPECT_EQ(first["frames"], 437);
  EXPECT_EQ(first["truth_scored"], 133);
  EXPECT_EQ(first["matches"], j["matches"]);
  EXPECT_EQ(second["frames"], 436);
  EXPECT_EQ(second["truth_scored"], 0);
  EXPECT_LE(int(second["false_positives"]), 10);
  const auto bad_range = test::run_cli("eval-tracking " + bag + " --scans 10:900");
  EXPECT_EQ(bad_range.exit_code, 1);
  EXPECT_NE(bad_range.output.find("--scans"), std::string::npos) << bad_range.output;

  // Every bearing: all 153 annotations scored.
  const auto all = eval_json(bag + " --truth-wedge -180 180");
  ASSERT_FALSE(all.is_null());
  EXPECT_EQ(all["truth_scored"], 153);
  EXPECT_EQ(all["frames_with_truth"], 123);
}

// --losses: where each of the 133 scored annotated persons is lost in the legs pipeline.
// Measured with the shipped settings: no segment 0, not a candidate 27, background 1, not a
// leg 13, occupied space 7, no person track 5, not reported 33, reported beyond the gate 4,
// reported 43 (before unjudged blobs were kept out of the person grid: not a candidate 30, not
// a leg 17, occupied 54, no person track 2, not reported 23, reported 2). Leg-sized returns
// kept out of the occupancy grid (--compact-occupancy 0): occupied 2, not reported 42,
// reported 39. Now the confirmation rules, then the classifier.
TEST(CliEvalTracking, LossesTellWhereTheAnnotatedPersonsAreLost) {
  FIELDLIDAR_REQUIRE_DATA(kBag);
  const auto dir = test::temp_dir("eval_tracking_losses");
  const auto bag = test::quoted(test::data_file(kBag));
  const auto csv = dir / "losses.csv", png = dir / "losses.png";
  const auto j =
      eval_json(bag + " --losses-csv " + test::quoted(csv) + " --losses-png " + test::quoted(png));
  ASSERT_FALSE(j.is_null());
  const auto& l = j["losses"];
  int sum = 0;
  for (const auto& [name, n] : l.items()) sum += int(n);
  EXPECT_EQ(sum, 133);
  EXPECT_EQ(int(l["no_segment"]), 0);  // every annotated person is seen by the laser
  EXPECT_LE(int(l["occupied"]), 10);
  EXPECT_GE(int(l["reported"]), 43);
  EXPECT_LE(int(l["not_candidate"]) + int(l["not_leg"]), 45);
  EXPECT_GE(int(l["reported"]), int(j["matches"]));
  std::ifstream in(csv);
  std::string line;
  int rows = 0;
  std::getline(in, line);
  EXPECT_EQ(line, "frame,truth_id,x_m,y_m,range_m,bearing_deg,loss");
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 133);
  // The picture of them in the sensor frame.
  ASSERT_TRUE(std::filesystem::exists(png));
  const auto png_bytes = std::filesystem::file_size(png);
  EXPECT_GT(png_bytes, 10000u);
  // The files are not replaced without --force, and that is said before the bag is run.
  const auto again = test::run_cli("eval-tracking " + bag + " --losses-csv " + test::quoted(csv));
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.output.find("--force"), std::string::npos) << again.output;
  const auto again_png =
      test::run_cli("eval-tracking " + bag + " --losses-png " + test::quoted(png));
  EXPECT_EQ(again_png.exit_code, 1);
  EXPECT_NE(again_png.output.find("losses.png"), std::string::npos) << again_png.output;
  EXPECT_EQ(std::filesystem::file_size(png), png_bytes);

  const auto kept = eval_json(bag + " --losses --compact-occupancy 0");
  ASSERT_FALSE(kept.is_null());
  EXPECT_LE(int(kept["losses"]["occupied"]), 5);
  EXPECT_GE(int(kept["losses"]["reported"]), 37);

  const auto refused = test::run_cli("eval-tracking " + bag + " --losses --detections x.csv");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.output.find("--detections"), std::string::npos) << refused.output;
}

TEST(CliEvalTracking, DetectionsCsvOfLegsGivesTheSameFigures) {
  FIELDLIDAR_REQUIRE_DATA(kBag);
  const auto dir = test::temp_dir("eval_tracking_csv");
  const auto bag = test::quoted(test::data_file(kBag));
  const auto csv = dir / "legs.csv";
  const auto legs = test::run_cli("legs " + bag + " --force --out " + test::quoted(csv));
  ASSERT_EQ(legs.exit_code, 0) << legs.output;
  for (const char* wedge : {"", " --truth-wedge -180 180"}) {
    const auto run = eval_json(bag + wedge);
    const auto read = eval_json(bag + wedge + " --detections " + test::quoted(csv));
    ASSERT_FALSE(run.is_null());
    ASSERT_FALSE(read.is_null());
    for (const char* k : {"tracked_persons", "tracked_scored", "matches", "misses",
                          "false_positives", "id_switches", "mota"})
      EXPECT_EQ(run[k], read[k]) << k << wedge;
  }
  // A row whose stamp is no scan's: an error naming the file and line.
  std::ofstream(dir / "bad.csv") << "stamp,kind,x,y,track_id\n12.5,person,1,0,3\n";
  const auto bad =
      test::run_cli("eval-tracking " + bag + " --detections " + test::quoted(dir / "bad.csv"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("bad.csv:2"), std::string::npos) << bad.output;
}

TEST(CliEvalTracking, SimulatedFolderScoresPeopleCsvInTheLidarFrame) {
  const auto dir = test::temp_dir("eval_tracking_sim");
  const auto sim = test::run_cli("simulate --scene lawn --frames 20 --seed 0 --force --out " +
                                 test::quoted(dir));
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  const auto j = eval_json(test::quoted(dir));
  ASSERT_FALSE(j.is_null());
  // The operator walking ahead of the mower, one person per frame, all bearings scored. When
  // written: 18 of 20 found (the first two frames confirm the track), MOTP 0.068 m, no id switch,
  // no false person.
  EXPECT_EQ(j["frames"], 20);
  EXPECT_EQ(j["truth_scored"], 20);
  EXPECT_TRUE(j["truth_wedge_deg"].is_null());
  EXPECT_GE(double(j["recall"]), 0.85);
  EXPECT_GE(double(j["mota"]), 0.85);
  EXPECT_LT(double(j["motp_m"]), 0.15);  // a wrong world -> lidar transform would be metres off
  EXPECT_EQ(j["id_switches"], 0);
  // The operator is hit by ~250-340 returns per sweep: all of them pass 100, none 100000.
  const auto seen = eval_json(test::quoted(dir) + " --truth-min-points 100");
  ASSERT_FALSE(seen.is_null());
  EXPECT_EQ(seen["truth_scored"], 20);
  const auto none = eval_json(test::quoted(dir) + " --truth-min-points 100000");
  ASSERT_FALSE(none.is_null());
  EXPECT_EQ(none["truth_scored"], 0);
  EXPECT_EQ(none["false_positives"], j["tracked_persons"]);

  // Its frame files carry no stamps, so a detections CSV cannot be paired with them.
  std::ofstream(dir / "det.csv") << "stamp,kind,x,y,track_id\n";
  const auto r = test::run_cli("eval-tracking " + test::quoted(dir) + " --detections " +
                               test::quoted(dir / "det.csv"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--detections"), std::string::npos) << r.output;

  // A folder that no simulation wrote: said so.
  const auto empty = test::temp_dir("eval_tracking_empty");
  const auto e = test::run_cli("eval-tracking " + test::quoted(empty));
  EXPECT_EQ(e.exit_code, 1);
  EXPECT_NE(e.output.find("not a folder written by `fieldlidar simulate`"), std::string::npos)
      << e.output;
}

// A people.csv with no one in it (empty, or its header alone) scores nothing: every track would
// be a false positive against nobody (MOTA -inf). An error, before the tracker runs.
// The 2D laser of a robot following its operator 2.5 m ahead across a rough lawn (6 cm bumps:
// the scan plane pitches and meets the ground a few metres out), the legs pipeline matching the
// scans for its own ego-motion. Its ground line travels with the robot and pulled the matching
// away by metres a scan: measured on scene seed 1 (400 scans) recall 0.780, 10 id switches, 24
// false persons before the matching's motion bounds (ScanMatcher2DConfig::max_speed_m_s,
// max_accel_m_s2); 0.970, none and none since.
TEST(CliEvalTracking, RoughLawnFollowedWithA2DLaserKeepsTheOperatorTracked) {
  const auto dir = test::temp_dir("cli_eval_tracking_rough");
  const auto sim = test::run_cli(
      "simulate --scene lawn --sensor laser2d --rough 0.06 --frames 400 --seed 1 --out " +
      test::quoted(dir));
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  const auto j = eval_json(test::quoted(dir) + " --truth-min-points 1");
  ASSERT_FALSE(j.is_null());
  EXPECT_EQ(j["truth_scored"], 400);
  EXPECT_GE(double(j["recall"]), 0.93);
  EXPECT_LE(int(j["id_switches"]), 2);
  EXPECT_LE(int(j["false_positives"]), 10);
  // Followed on that recording without its odometry: the target held in 53.6 % of the scans
  // since chosen before the motion bounds and the quick retake of a new detector person where
  // the target walks on (FollowConfig::quick_retake_s); 100 % since.
  const auto replay = test::run_cli("follow --replay " + test::quoted(dir) + " --out " +
                                    test::quoted(dir / "replay"));
  ASSERT_EQ(replay.exit_code, 0) << replay.output;
  std::ifstream in(dir / "replay" / "summary.json");
  const auto m = nlohmann::json::parse(in)["metrics"];
  EXPECT_GE(double(m["target_held_fraction"]), 0.97);
  EXPECT_EQ(m["distinct_target_ids"], 1);
  // Placed by the recording's poses instead of the matching (`--odom`, here the simulator's TUM
  // file of the sensor): measured recall 0.975, no id switch, no false person.
  const auto placed = eval_json(test::quoted(dir) + " --truth-min-points 1 --odom " +
                                test::quoted(dir / "poses_tum.txt"));
  ASSERT_FALSE(placed.is_null());
  EXPECT_GE(double(placed["recall"]), 0.95);
  EXPECT_EQ(placed["id_switches"], 0);
  EXPECT_LE(int(placed["false_positives"]), 3);
  // `legs --odom` takes the same poses; a missing pose file is named.
  auto r = test::run_cli("legs " + test::quoted(dir / "pcd") + " --odom " +
                         test::quoted(dir / "poses_tum.txt") + " --out " +
                         test::quoted(dir / "legs.csv"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // Poses covering the first 9.9 s only: the scans past 10.4 s are said to be placed at its end.
  {
    std::ifstream in(dir / "poses_tum.txt");
    std::ofstream out(dir / "short_tum.txt");
    std::string line;
    for (int k = 0; k < 101 && std::getline(in, line); ++k) out << line << "\n";
  }
  r = test::run_cli("legs " + test::quoted(dir / "pcd") + " --odom " +
                    test::quoted(dir / "short_tum.txt") + " --out " +
                    test::quoted(dir / "legs3.csv"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("frames lie outside the time span of --odom"), std::string::npos)
      << r.output;
  r = test::run_cli("legs " + test::quoted(dir / "pcd") + " --odom " +
                    test::quoted(dir / "nope.txt") + " --out " + test::quoted(dir / "legs2.csv"));
  EXPECT_NE(r.output.find("--odom " + (dir / "nope.txt").string() + ": no such file"),
            std::string::npos)
      << r.output;
}

TEST(CliEvalTracking, PeopleCsvWithoutAPersonIsAnError) {
  const auto dir = test::temp_dir("eval_tracking_no_person");
  const auto sim =
      test::run_cli("simulate --scene lawn --frames 2 --seed 0 --force --out " + test::quoted(dir));
  ASSERT_EQ(sim.exit_code, 0) << sim.output;
  std::string header;
  std::getline(std::ifstream(dir / "people.csv"), header);
  for (const std::string& text : {header + "\n", std::string()}) {
    std::ofstream(dir / "people.csv") << text;
    const auto r = test::run_cli("eval-tracking " + test::quoted(dir));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("people.csv: no annotated person"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("MOTA"), std::string::npos) << r.output;
  }
  // Range errors say the range, not a 309-digit DBL_MAX.
  for (const std::string gate : {"0", "inf", "nan"}) {
    const auto r = test::run_cli("eval-tracking " + test::quoted(dir) + " --gate " + gate);
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find("--gate: must be"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("> 0"), std::string::npos) << r.output;
    EXPECT_LT(r.output.size(), 200u) << r.output;
  }
}

TEST(CliEvalTracking, WrongAnnotationTopicIsAnErrorListingTheTopics) {
  FIELDLIDAR_REQUIRE_DATA(kBag);
  const auto bag = test::quoted(test::data_file(kBag));
  auto r = test::run_cli("eval-tracking " + bag + " --truth /odom");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("not leg_tracker/Person"), std::string::npos) << r.output;
  r = test::run_cli("eval-tracking " + bag + " --truth /people");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("/ground_truth_people_tracks [leg_tracker/Person, 153]"),
            std::string::npos)
      << r.output;
  r = test::run_cli("eval-tracking " + bag + " --gate 0");
  EXPECT_NE(r.exit_code, 0);
  r = test::run_cli("eval-tracking " + bag + " --truth-wedge 12 -80");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("must be below"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace fieldlidar
