// The simulator's trees.csv read as true trees, and detection scores of `fieldlidar trunks`.
#include "support/trunks_truth.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iterator>
#include <string>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/file_util.hpp"
#include "fieldlidar/io/trajectory_io.hpp"
#include "support/csv_number.hpp"

namespace fieldlidar::app {

namespace {

/// The columns read, in the order of trees.csv.
constexpr const char* kColumns[] = {"id",     "base_x_m", "base_y_m", "base_z_m",
                                    "axis_x", "axis_y",   "axis_z",   "dbh_m"};

}  // namespace

std::vector<TrueTree> read_true_trees(const std::filesystem::path& path) {
  const auto bytes = io::read_file_bytes(path);
  const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::vector<TrueTree> out;
  std::size_t pos = text.find('\n'), line = 1;
  while (pos != std::string::npos && pos + 1 < text.size()) {
    const std::size_t end = text.find('\n', pos + 1);
    std::string row = text.substr(pos + 1, end == std::string::npos ? end : end - pos - 1);
    pos = end;
    ++line;
    if (!row.empty() && row.back() == '\r') row.pop_back();
    if (row.empty()) continue;
    std::vector<double> v;
    std::size_t a = 0;
    while (v.size() < std::size(kColumns)) {
      const std::size_t b = row.find(',', a);
      const std::string cell = row.substr(a, b == std::string::npos ? b : b - a);
      v.push_back(csv_number(cell, path, line, kColumns[v.size()]));
      if (b == std::string::npos) break;
      a = b + 1;
    }
    if (v.size() < std::size(kColumns))
      throw Error(
          fmt::format("{}: line {}: expected id,base_x_m,base_y_m,base_z_m,axis_x,axis_y,"
                      "axis_z,dbh_m,...",
                      path.string(), line));
    const Eigen::Vector3d base(v[1], v[2], v[3]), axis = Eigen::Vector3d(v[4], v[5], v[6]);
    if (!(axis.normalized().z() > 0.1))
      throw Error(fmt::format("{}: line {}: axis ({:g}, {:g}, {:g}) does not point up",
                              path.string(), line, v[4], v[5], v[6]));
    if (!(v[7] > 0))
      throw Error(fmt::format("{}: line {}: dbh_m {:g} is not a positive diameter", path.string(),
                              line, v[7]));
    out.push_back({base + axis.normalized() * (1.3 / axis.normalized().z()), v[7]});
  }
  // Recall over no tree would read 1.0: a header alone is a broken truth, not a perfect score.
  if (out.empty()) throw Error(path.string() + ": holds no tree");
  return out;
}

std::vector<TrueTree> moved(const std::vector<TrueTree>& trees, const Pose& T_frame_world) {
  std::vector<TrueTree> out = trees;
  for (auto& t : out) t.at_dbh = T_frame_world * t.at_dbh;
  return out;
}

void print_trunk_scores(const std::vector<forest::Tree>& trees, const std::vector<TrueTree>& truth,
                        const std::vector<Eigen::Vector3d>& path, double radius_m) {
  auto near_path = [&](const Eigen::Vector3d& p, double r) {
    if (path.empty()) return true;
    for (const auto& q : path)
      if ((q - p).head<2>().norm() <= r) return true;
    return false;
  };
  std::vector<char> used(truth.size(), 0);
  int scored = 0, detected = 0, matched = 0, uncertain = 0;
  double dbh_sq = 0, dbh_sum = 0, pos_sq = 0;
  for (const auto& t : truth) scored += near_path(t.at_dbh, radius_m);
  for (const auto& d : trees) {
    const Eigen::Vector3d p = d.at_height(1.3);
    if (!near_path(p, radius_m + 0.5)) continue;
    std::size_t best = truth.size();
    double bd = 0.3;
    for (std::size_t k = 0; k < truth.size(); ++k)
      if (!used[k] && (truth[k].at_dbh - p).head<2>().norm() < bd) {
        bd = (truth[k].at_dbh - p).head<2>().norm();
        best = k;
      }
    if (best < truth.size() && !near_path(truth[best].at_dbh, radius_m)) {
      used[best] = 1;
      continue;
    }
    ++detected;
    if (best == truth.size()) continue;
    used[best] = 1;
    ++matched;
    pos_sq += bd * bd;
    if (d.dbh_uncertain) {
      ++uncertain;
      continue;
    }
    dbh_sq += std::pow(d.dbh_m - truth[best].dbh_m, 2);
    dbh_sum += d.dbh_m - truth[best].dbh_m;
  }
  const double m = std::max(matched, 1), md = std::max(matched - uncertain, 1);
  fmt::print(
      "truth: {} trees{}, {} detected, {} matched: precision {:.3f}, recall {:.3f}, DBH RMSE "
      "{:.4f} m, bias {:+.4f} m (over {} with a measured DBH; {} marked uncertain), position "
      "RMSE {:.4f} m\n",
      scored, path.empty() ? "" : fmt::format(" within {:g} m of the sensor's path", radius_m),
      detected, matched, detected ? double(matched) / detected : 1.0,
      scored ? double(matched) / scored : 1.0, std::sqrt(dbh_sq / md), dbh_sum / md,
      matched - uncertain, uncertain, std::sqrt(pos_sq / m));
}

std::optional<Pose> simulator_scan_pose(const std::filesystem::path& scan) {
  const auto folder = scan.parent_path();
  const std::string stem = scan.stem().string();
  if (folder.filename() != "pcd" || stem.empty() || stem.size() > 9 ||
      !std::all_of(stem.begin(), stem.end(), [](unsigned char c) { return std::isdigit(c); }))
    return std::nullopt;
  const auto poses_file = folder.parent_path() / "poses.txt";
  if (!std::filesystem::exists(poses_file)) return std::nullopt;
  const auto poses = io::read_kitti_poses(poses_file);
  const std::size_t index = std::stoul(stem);
  if (index >= poses.size())
    throw Error(
        fmt::format("{}: no pose for scan {} ({} rows)", poses_file.string(), index, poses.size()));
  return poses[index].pose;
}

}  // namespace fieldlidar::app
