// Random start/goal pairs on the terrain scenes of seeds 2-5 (data/navigate_pairs_terrain_seed2..5
// .csv, 12 each, drawn by scripts/navigate_random_pairs.py; slow: about a minute in Release), the
// navigate loop with its defaults. Judged as a whole, with bounds from the figures measured:
// - the 36 pairs whose goal the Hybrid A* plan on the truth map reaches: every one arrives; 31
//   of 36 within 1.15 x the truth plan, mean ratio 1.096, largest 2.013 (seed 4 p9 tries the
//   gap at the end of the diagonal wall and turns back; 2 p4 1.707, 3 p3 1.404: detours round
//   rock fields whose gaps the map's obstacle halo closes). Before a lone ring's plane was read
//   as level (TraversabilityConfig::min_plane_spread_m) 32 were within 1.15, mean 1.050,
//   largest 1.288: seeds 2-5 lost by it what seeds 6-21 and the held-out seeds gained
//   (docs/navigate.md); with it, before the sweeps were segmented in the robot's own frame
//   (loops::navigate_fusion_config), seed 5 p9 was reported unreachable after 105 m. Two drives put
//   the footprint on truth-impassable cells: seed 2 p9, 10 frames (its corner 4 cm into the cell
//   west of a rock by the terrace's north-west corner, a cell the map held unknown as the robot
//   passed, 2 returns: in the blind disk then, seen only edge-on before; its east and north
//   neighbours were blocked by their step, and the obstacle halo grows only from cells with
//   obstacle returns), and seed 4 p9, 11 frames (5 cm into a rock's cell on its detour round the
//   wall's west; seed 3 p3, 12 frames turning onto its goal beside the ditch's end before, now 0);
// - the 6 goals on the walled-in terrace: each reported unreachable, 0 frames (8 before, seed 3
//   p0: the footprint's corner on the truth cell at the terrace's corner);
// - the 6 starts on the terrace (truth: no way off): all 6 reported unreachable, 0 frames. Before
//   the drop bands (the foot of the step, hidden by its lip, seen from above as a band of unseen
//   cells between ground cells 0.5 m apart in height: loops::mark_drop_bands) all 6 drove off it
//   (21-62 frames each); with them 4 were reported and two drove off (81 frames), the step
//   1.5-2.5 m from the start, never outside the blind disk of the start or the approach, until
//   the blind drops (loops::mark_blind_drops: the lower ground beyond the blind disk does not
//   lead back up to the robot's).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "fieldlidar/loops/navigate.hpp"
#include "fieldlidar/loops/navigate_pairs.hpp"
#include "fieldlidar/sim/scenes.hpp"

using namespace fieldlidar;

namespace {

/// The whole of a run of random pairs.
struct Tally {
  int reachable = 0, arrived = 0, over = 0, to_terrace = 0, said_unreachable = 0;
  int on_terrace = 0, on_terrace_said_unreachable = 0, on_terrace_drives_with_frames = 0;
  int reachable_drives_with_frames = 0;
  std::size_t reachable_frames = 0, to_terrace_frames = 0, on_terrace_frames = 0;
  double ratio_sum = 0, ratio_max = 0;
  double mean() const { return arrived ? ratio_sum / arrived : 0.0; }
};

/// Drives every pair of navigate_pairs_terrain_seed<first..last>.csv with the defaults; a
/// reachable pair may put the footprint on truth-impassable cells for at most
/// max_frames(seed, name) frames, a start on the terrace (driving off its step) for at most
/// max_on_terrace_frames.
template <class MaxFrames>
Tally drive_random_pairs(std::uint64_t first, std::uint64_t last, MaxFrames max_frames,
                         std::size_t max_on_terrace_frames) {
  loops::NavigateConfig cfg;
  // The expansion budget, not the load on the test machine, ends a walled-in search.
  cfg.planner.time_budget_ms = 4000.0;
  Tally t;
  for (std::uint64_t seed = first; seed <= last; ++seed) {
    const sim::Scene scene = sim::make_terrain_scene({}, seed);
    const std::string file = std::string(FIELDLIDAR_NAVIGATE_DATA) +
                             "/navigate_pairs_terrain_seed" + std::to_string(seed) + ".csv";
    const auto pairs = loops::read_navigate_pairs(file);
    EXPECT_EQ(pairs.size(), 12u) << file;
    for (const auto& p : pairs) {
      const auto r = loops::run_navigate(scene, SensorModel::vlp16(), p.start, p.goal, cfg);
      std::printf("seed %llu %-16s %-11s ratio %6.3f, %4zu frames on impassable  %s\n",
                  static_cast<unsigned long long>(seed), p.name.c_str(),
                  loops::to_string(r.outcome), r.length_ratio, r.frames_on_impassable,
                  r.reason.c_str());
      std::fflush(stdout);
      if (p.expect == "arrived") {
        ++t.reachable;
        EXPECT_EQ(r.truth_status, planning::PlanStatus::kSuccess) << p.name;
        t.arrived += r.outcome == loops::NavigateOutcome::kArrived;
        t.reachable_frames += r.frames_on_impassable;
        t.reachable_drives_with_frames += r.frames_on_impassable > 0;
        EXPECT_LE(r.frames_on_impassable, max_frames(seed, p.name))
            << "seed " << seed << " " << p.name;
        if (r.outcome == loops::NavigateOutcome::kArrived) {
          t.ratio_sum += r.length_ratio;
          t.ratio_max = std::max(t.ratio_max, r.length_ratio);
          t.over += r.length_ratio > 1.15;
        }
      } else {
        EXPECT_NE(r.truth_status, planning::PlanStatus::kSuccess) << p.name;
        if (p.name.ends_with("_to_terrace")) {
          ++t.to_terrace;
          t.said_unreachable += r.outcome == loops::NavigateOutcome::kUnreachable;
          t.to_terrace_frames += r.frames_on_impassable;
        } else {
          EXPECT_TRUE(p.name.ends_with("_on_terrace")) << p.name;
          EXPECT_LE(r.frames_on_impassable, max_on_terrace_frames)
              << "seed " << seed << " " << p.name;
          ++t.on_terrace;
          t.on_terrace_said_unreachable += r.outcome == loops::NavigateOutcome::kUnreachable;
          t.on_terrace_frames += r.frames_on_impassable;
          t.on_terrace_drives_with_frames += r.frames_on_impassable > 0;
        }
      }
    }
  }
  std::printf(
      "reachable %d: arrived %d, drives on truth-impassable cells %d (%zu frames), over 1.15: "
      "%d, mean ratio %.3f, largest %.3f; goals on the terrace %d: unreachable %d, frames %zu; "
      "starts on the terrace %d: unreachable %d, drives with frames %d (%zu frames)\n",
      t.reachable, t.arrived, t.reachable_drives_with_frames, t.reachable_frames, t.over, t.mean(),
      t.ratio_max, t.to_terrace, t.said_unreachable, t.to_terrace_frames, t.on_terrace,
      t.on_terrace_said_unreachable, t.on_terrace_drives_with_frames, t.on_terrace_frames);
  return t;
}

/// Bounds on a run of random pairs, from its measured figures.
struct Bounds {
  int reachable, arrived_min, drives_with_frames_max;
  std::size_t frames_max;
  int over_max;
  double mean_max, ratio_max;
  int to_terrace, on_terrace;
};

void expect_within(const Tally& t, const Bounds& b) {
  EXPECT_EQ(t.reachable, b.reachable);
  EXPECT_GE(t.arrived, b.arrived_min);
  EXPECT_LE(t.reachable_drives_with_frames, b.drives_with_frames_max);
  EXPECT_LE(t.reachable_frames, b.frames_max);
  EXPECT_LE(t.over, b.over_max);
  EXPECT_LE(t.mean(), b.mean_max);
  EXPECT_LE(t.ratio_max, b.ratio_max);
  EXPECT_EQ(t.to_terrace, b.to_terrace);
  EXPECT_EQ(t.said_unreachable, t.to_terrace);
  EXPECT_EQ(t.on_terrace, b.on_terrace);
  EXPECT_EQ(t.on_terrace_said_unreachable, t.on_terrace);
  EXPECT_EQ(t.on_terrace_frames, 0u);
}

}  // namespace

TEST(NavigatePairs, RandomPairsSeeds2To5) {
  const Tally t = drive_random_pairs(
      2, 5,
      [](std::uint64_t seed, const std::string& name) {
        if (seed == 2 && name == "p9") return 10u;  // see above
        return seed == 4 && name == "p9" ? 11u : 0u;
      },
      0);
  expect_within(t, {.reachable = 36,
                    .arrived_min = 36,  // every one
                    .drives_with_frames_max = 2,
                    .frames_max = 22,
                    .over_max = 5,
                    .mean_max = 1.10,
                    .ratio_max = 2.05,
                    .to_terrace = 6,
                    .on_terrace = 6});
  EXPECT_LE(t.to_terrace_frames, 10u);
}

// 192 more random pairs, seeds 6-21 (navigate_pairs_terrain_seed6..21.csv; two tests of about
// two and a half minutes each in Release, so that they run side by side), the map's failures on
// which were looked at for the ground and overhang changes of issue 17 (seeds 18-21 drawn after
// the first two were chosen): a fence round what the loop does on them, with what it still gets
// wrong.
// - 148 pairs the truth plan reaches: 144 arrive (141 when a blocked goal was judged from 8 m),
//   10 over 1.15 x the truth plan (mean 1.050, largest 1.980). Not arrived: 2 goals on hill
//   flanks whose cells the map finds raised even from near (seeds 8, 16), one start beside the
//   hill with no path (seed 7 p6), one goal after a 65 m search (seed 9 p11, time limit).
//   11 drives put the footprint on truth-impassable cells: starts 1-2 m from a rock or the
//   ditch's end, in the blind disk of the start and of the approach (seed 21 p9 turns into
//   the ditch it starts beside, in the blind disk of every sweep, and is stopped by the tilt
//   stop with its front wheels down its wall: 66 frames, 95 driving through without it), and
//   gaps between rocks the map leaves open and the truth's discs close; 282 frames in all (311
//   without the tilt stop, 374 before the blind drops: seed 11 p4, beside the ditch's end, 92 ->
//   29).
// - the 26 goals on the terrace: reported unreachable (8 frames in all); the 18 starts there are
//   all reported unreachable, 0 frames (before the drop bands all 18 drove off its step, up to
//   119 frames; with them 15 were reported and 4 drives touched the step, 126 frames, until the
//   blind drops).
// Seeds 6-13: 72 of 75 arrive (not seed 7 p6, 8 p9, 9 p11), 3 over 1.15 (mean 1.027, largest
// 1.370), 6 drives with frames (127: seed 8 p8 51, 9 p2 21, 11 p0 15, 11 p4 29, 13 p8 10, 13 p10
// 1); 13 goals and 8 starts on the terrace. Seeds 14-21: 72 of 73 (not seed 16 p2), 7 over 1.15
// (mean 1.071, largest 1.980), 5 drives with frames (155: seed 18 p3 17, 20 p9 12, 20 p11 27, 21
// p9 66, 21 p11 33); 13 goals (8 frames) and 10 starts on the terrace. Since a lone ring's plane
// is read as level and the sweeps are segmented in the robot's own frame
// (loops::navigate_fusion_config): seeds 6-13 73 of 75 (not 7 p6, 9 p11), 2 over 1.15 (mean
// 1.014, largest 1.332), 5 drives with frames (83: 8 p8 26, 9 p2 19, 11 p0 8, 11 p4 29, 13 p10
// 1); seeds 14-21 71 of 73 (14 p3 fails on 31 emergency stops 3.5 m from its start, 16 p2 is
// reported unreachable), 6 over 1.15 (mean 1.047, largest 1.733), 4 drives with frames (106: 18
// p3 17, 20 p9 12, 20 p11 11, 21 p9 66); since ground driven over is no guess
// (NavigateConfig::driven_clears_guesses) 14 p3 arrives (72 of 73, ratio 1.125). Since
// periodic plans that gain little are put off (NavigateConfig::replan_switch_gain): seeds 2-5 36
// of 36 (mean 1.078, largest 2.016, 1 drive with frames, 11); seeds 6-13 73 of 75 (9 p11 now
// arrives, 9 p3 is reported unreachable), mean 1.012, 5 drives with frames (91); seeds 14-21 72
// of 73, mean 1.043, largest 1.812, 5 drives with frames (117). The other bounds stay those
// measured before.
TEST(NavigatePairs, RandomPairsSeeds6To13) {
  expect_within(drive_random_pairs(
                    6, 13, [](std::uint64_t, const std::string&) { return 100u; }, 0),
                {.reachable = 75,
                 .arrived_min = 72,
                 .drives_with_frames_max = 6,
                 .frames_max = 135,
                 .over_max = 3,
                 .mean_max = 1.035,
                 .ratio_max = 1.40,
                 .to_terrace = 13,
                 .on_terrace = 8});
}

TEST(NavigatePairs, RandomPairsSeeds14To21) {
  const auto frames_max = [](std::uint64_t seed, const std::string& name) {
    return seed == 21 && name == "p9" ? 70u : 100u;
  };
  expect_within(drive_random_pairs(14, 21, frames_max, 0), {.reachable = 73,
                                                            .arrived_min = 72,
                                                            .drives_with_frames_max = 5,
                                                            .frames_max = 160,
                                                            .over_max = 7,
                                                            .mean_max = 1.075,
                                                            .ratio_max = 2.05,
                                                            .to_terrace = 13,
                                                            .on_terrace = 10});
}
