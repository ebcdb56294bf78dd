#include "fieldlidar/people/person_loss.hpp"

#include <algorithm>
#include <limits>

namespace fieldlidar::people {

std::string_view person_loss_name(PersonLoss loss) {
  constexpr std::array<std::string_view, kPersonLosses> names = {
      "no_segment", "not_candidate",   "not_foreground", "background",           "not_leg",
      "occupied",   "no_person_track", "not_reported",   "reported_beyond_gate", "reported"};
  return names[std::size_t(loss)];
}

PersonLoss person_loss(const Eigen::Vector2d& truth_m, std::span<const SegmentTrace> segments,
                       std::span<const PipelinePerson> reported, const PersonLossConfig& c) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& p : reported) nearest = std::min(nearest, (p.position_m - truth_m).norm());
  if (nearest < c.gate_m) return PersonLoss::kReported;
  if (nearest < c.near_m) return PersonLoss::kReportedBeyondGate;
  auto furthest = PersonLoss::kNoSegment;
  auto raise = [&](PersonLoss l) { furthest = std::max(furthest, l); };
  for (const auto& s : segments) {
    if ((s.mean_m - truth_m).norm() > c.segment_radius_m) continue;
    switch (s.fate) {
      case SegmentFate::kNotCandidate:
        raise(PersonLoss::kNotCandidate);
        break;
      case SegmentFate::kNotForeground:
        raise(PersonLoss::kNotForeground);
        break;
      case SegmentFate::kWorldBackground:
      case SegmentFate::kSensorBackground:
        raise(PersonLoss::kBackground);
        break;
      case SegmentFate::kNotLeg:
        raise(PersonLoss::kNotLeg);
        break;
      case SegmentFate::kOccupied:
        raise(PersonLoss::kOccupied);
        break;
      case SegmentFate::kPersonInput:
        raise(s.person >= 0 ? PersonLoss::kNotReported : PersonLoss::kNoPersonTrack);
        break;
    }
  }
  return furthest;
}

}  // namespace fieldlidar::people
