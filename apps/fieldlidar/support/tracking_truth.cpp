#include "support/tracking_truth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <nlohmann/json.hpp>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"
#include "fieldlidar/io/trajectory_io.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out(1);
  for (char c : line) {
    if (c == ',')
      out.emplace_back();
    else
      out.back().push_back(c);
  }
  if (!out.back().empty() && out.back().back() == '\r') out.back().pop_back();
  return out;
}

double to_number(const std::string& s, const std::string& where) {
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size() && std::isfinite(v)) return v;
  } catch (...) {
  }
  throw Error(where + ": '" + s + "' is not a finite number");
}

/// Rows of a CSV with a header line as column name -> value callbacks.
template <class Row>
void read_csv(const fs::path& path, const std::vector<std::string>& columns, Row row) {
  const auto bytes = io::read_file_bytes(path);
  const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::vector<int> where(columns.size(), -1);
  std::size_t start = 0, line_no = 0;
  while (start < text.size()) {
    const std::size_t eol = std::min(text.find('\n', start), text.size());
    const auto cells = split_csv(text.substr(start, eol - start));
    start = eol + 1;
    ++line_no;
    if (line_no == 1) {
      for (std::size_t c = 0; c < columns.size(); ++c) {
        const auto it = std::find(cells.begin(), cells.end(), columns[c]);
        if (it == cells.end())
          throw Error(path.string() + ": no column '" + columns[c] + "' in the header");
        where[c] = int(it - cells.begin());
      }
      continue;
    }
    if (cells.size() == 1 && cells[0].empty()) continue;
    std::vector<std::string> picked;
    for (int w : where) {
      if (std::size_t(w) >= cells.size())
        throw Error(path.string() + ":" + std::to_string(line_no) + ": too few columns");
      picked.push_back(cells[std::size_t(w)]);
    }
    row(picked, path.string() + ":" + std::to_string(line_no));
  }
}

std::string only_scan_topic(const std::string& bag) {
  std::string found;
  for (const auto& t : io::bag_topics(bag))
    if (t.datatype == "sensor_msgs/LaserScan" || t.datatype == "sensor_msgs/PointCloud2") {
      if (!found.empty()) throw Error(bag + ": several scan topics, choose one with --topic");
      found = t.name;
    }
  if (found.empty()) throw Error(bag + ": no sensor_msgs/LaserScan or PointCloud2 topic");
  return found;
}

}  // namespace

TrackingTruth bag_person_truth(const std::string& bag, const std::string& scan_topic,
                               const std::string& person_topic) {
  TrackingTruth t;
  t.bag = true;
  t.frames_input = bag;
  t.topic = scan_topic.empty() ? only_scan_topic(bag) : scan_topic;
  for (const auto& scan : io::read_person_annotations(bag, t.topic, person_topic)) {
    t.stamps_s.push_back(scan.scan_stamp_s);
    auto& v = t.persons.emplace_back();
    for (const auto& p : scan.people)
      v.push_back({p.id, Eigen::Vector2d(p.pose.translation().x(), p.pose.translation().y())});
  }
  return t;
}

TrackingTruth simulated_person_truth(const fs::path& dir, double min_points) {
  if (!fs::exists(dir / "poses.txt"))
    throw Error(dir.string() +
                ": not a folder written by `fieldlidar simulate` (no poses.txt); eval-tracking "
                "reads such a folder or a bag with leg_tracker/Person annotations");
  if (!fs::exists(dir / "people.csv"))
    throw Error((dir / "people.csv").string() +
                ": no such file (the simulated scene has no people to score)");
  TrackingTruth t;
  t.frames_input = (dir / "pcd").string();
  const auto poses = io::read_kitti_poses(dir / "poses.txt", dir / "times.txt");
  t.persons.resize(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) t.stamps_s.push_back(poses[i].stamp_s);
  std::size_t rows = 0;
  read_csv(dir / "people.csv", {"frame", "id", "x_m", "y_m", "points"},
           [&](const std::vector<std::string>& c, const std::string& where) {
             ++rows;
             if (to_number(c[4], where + " points") < min_points) return;
             const double f = to_number(c[0], where + " frame");
             if (f < 0 || f >= double(poses.size()) || f != std::floor(f))
               throw Error(where + ": frame " + c[0] + " is not one of the " +
                           std::to_string(poses.size()) + " frames of poses.txt");
             const auto& T = poses[std::size_t(f)].pose;
             const Eigen::Vector3d world(to_number(c[2], where + " x_m"),
                                         to_number(c[3], where + " y_m"), T.translation().z());
             const Eigen::Vector3d local = T.inverse() * world;
             t.persons[std::size_t(f)].push_back(
                 {std::int64_t(to_number(c[1], where + " id")), local.head<2>()});
           });
  // Every track would be a false positive against nothing (MOTA -inf): the file is broken or the
  // scene had no one in it, and either way there is nothing to score.
  if (rows == 0) throw Error((dir / "people.csv").string() + ": no annotated person");
  return t;
}

std::string simulated_sensor(const fs::path& dir) {
  const fs::path meta = dir / "scene.json";
  if (!fs::exists(meta)) return {};
  const auto bytes = io::read_file_bytes(meta);
  try {
    const auto j = nlohmann::json::parse(bytes.begin(), bytes.end());
    return j.value("sensor", std::string());
  } catch (const nlohmann::json::exception& e) {
    throw Error(meta.string() + ": not valid JSON (" + e.what() + ")");
  }
}

PersonsPerFrame read_person_tracks_csv(const fs::path& csv, const std::vector<double>& stamps_s) {
  PersonsPerFrame out(stamps_s.size());
  std::vector<std::size_t> order(stamps_s.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return stamps_s[a] < stamps_s[b]; });
  read_csv(
      csv, {"stamp", "kind", "x", "y", "track_id"},
      [&](const std::vector<std::string>& c, const std::string& where) {
        if (c[1] != "person") return;
        const double stamp = to_number(c[0], where + " stamp");
        const auto it = std::lower_bound(order.begin(), order.end(), stamp,
                                         [&](std::size_t i, double s) { return stamps_s[i] < s; });
        std::size_t best = order.size();
        double best_dt = 1e-3;  // the CSV writes stamps to the microsecond
        for (auto j = it == order.begin() ? it : it - 1; j != order.end() && j <= it; ++j)
          if (std::abs(stamps_s[*j] - stamp) < best_dt)
            best = *j, best_dt = std::abs(stamps_s[*j] - stamp);
        if (best == order.size())
          throw Error(where + ": stamp " + c[0] + " is not the stamp of any scan of the input");
        out[best].push_back(
            {std::int64_t(to_number(c[4], where + " track_id")),
             Eigen::Vector2d(to_number(c[2], where + " x"), to_number(c[3], where + " y"))});
      });
  return out;
}

}  // namespace fieldlidar::app
