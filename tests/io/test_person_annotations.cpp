// leg_tracker/Person annotations: the decoder, and their pairing with scans by bag order on the
// leg_tracker benchmark bag.

#include <cstdint>
#include <cstring>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "test_data.hpp"

namespace fieldlidar {
namespace {

template <class T>
void put(std::vector<std::uint8_t>& b, T v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  b.insert(b.end(), p, p + sizeof(T));
}

TEST(LegTrackerPerson, DecodesPoseAndId) {
  std::vector<std::uint8_t> b;
  for (double v : {1.5, -2.25, 0.0, 0.0, 0.0, 0.0, 1.0}) put(b, v);  // position, quaternion
  put(b, std::uint32_t(1001));
  const auto p = io::parse_leg_tracker_person(b);
  EXPECT_EQ(p.id, 1001u);
  EXPECT_DOUBLE_EQ(p.pose.translation().x(), 1.5);
  EXPECT_DOUBLE_EQ(p.pose.translation().y(), -2.25);
  b.pop_back();  // truncated id
  EXPECT_THROW(io::parse_leg_tracker_person(b), Error);
}

TEST(LegTrackerPerson, PairedWithTheScanRecordedBeforeThem) {
  FIELDLIDAR_REQUIRE_DATA("legs_2d_tracking/general_tracking_moving_1.bag");
  const auto bag = test::data_file("legs_2d_tracking/general_tracking_moving_1.bag");
  const auto scans = io::read_person_annotations(bag, "/scan", "/ground_truth_people_tracks");
  ASSERT_EQ(scans.size(), 873u);
  std::size_t people = 0, annotated_scans = 0;
  std::set<std::uint32_t> ids;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    people += scans[i].people.size();
    annotated_scans += !scans[i].people.empty();
    for (const auto& p : scans[i].people) ids.insert(p.id);
    if (i > 0) {
      EXPECT_GT(scans[i].scan_stamp_s, scans[i - 1].scan_stamp_s);
    }
  }
  EXPECT_EQ(people, 153u);
  EXPECT_EQ(ids.size(), 12u);
  EXPECT_EQ(annotated_scans, 123u);
  // The first annotation follows scan 133: person 1, 4.76 m ahead and 2.81 m to the right.
  ASSERT_EQ(scans[133].people.size(), 1u);
  EXPECT_EQ(scans[133].people[0].id, 1u);
  EXPECT_NEAR(scans[133].people[0].pose.translation().x(), 4.76, 0.01);
  EXPECT_NEAR(scans[133].people[0].pose.translation().y(), -2.81, 0.01);
  EXPECT_THROW(io::read_person_annotations(bag, "/scan", "/odom"), Error);
  EXPECT_THROW(io::read_person_annotations(bag, "/odom", "/ground_truth_people_tracks"), Error);
}

}  // namespace
}  // namespace fieldlidar
