#pragma once
/// \file Where an annotated person is lost in LegPipeline2D: the furthest step that the scan
/// segments near the person reached (LegPipeline2DOutput::segments, with
/// LegPipeline2DConfig::trace_segments), or a reported person within the match gate. Summed
/// over a recording, it tells which step to fix first (segmentation and range, the classifier,
/// the background filters, the occupancy grid of non-person returns, the person tracker's
/// confirmation rules). Positions in the sensor frame of the scan, metres.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include <Eigen/Core>

#include "fieldlidar/people/legs_2d_pipeline.hpp"

namespace fieldlidar::people {

/// In the order of the pipeline's steps: each one means the person got no further.
enum class PersonLoss : std::uint8_t {
  kNoSegment,           ///< no segment near the person (out of range, not seen)
  kNotCandidate,        ///< segments scored at most candidate_score_min (or failed the shape tests)
  kNotForeground,       ///< seen through a gap only
  kBackground,          ///< on the slow world or sensor-frame background
  kNotLeg,              ///< candidates below the classifier's threshold, not carried by a track
  kOccupied,            ///< legs, but on the occupancy grid of non-person returns
  kNoPersonTrack,       ///< legs given to the person tracker that no track took
  kNotReported,         ///< legs of a person track that is not reported (yet)
  kReportedBeyondGate,  ///< a reported person near, but not within the gate
  kReported,            ///< a reported person within the gate
};
inline constexpr std::size_t kPersonLosses = 10;

/// A short name for reports ("no_segment", "not_candidate", ..., "reported").
std::string_view person_loss_name(PersonLoss loss);

struct PersonLossConfig {
  double segment_radius_m = 0.45;  ///< a segment whose mean is this near belongs to the person
  double gate_m = 0.75;            ///< a reported person strictly nearer matches (CLEAR MOT gate)
  double near_m = 1.5;             ///< a reported person within this is "beyond the gate"
};

/// The loss of an annotated person at `truth_m` in one scan, from the scan's segment trace and
/// the persons reported in it.
PersonLoss person_loss(const Eigen::Vector2d& truth_m, std::span<const SegmentTrace> segments,
                       std::span<const PipelinePerson> reported,
                       const PersonLossConfig& config = {});

/// Counts per loss, indexed by PersonLoss.
using PersonLossCounts = std::array<std::size_t, kPersonLosses>;

}  // namespace fieldlidar::people
