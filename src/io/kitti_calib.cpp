#include "fieldlidar/io/kitti_calib.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <vector>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/core/trajectory_metrics.hpp"
#include "fieldlidar/io/file_util.hpp"

namespace fieldlidar::io {

namespace {

std::vector<double> parse_numbers(std::string_view rest, const std::string& where) {
  std::vector<double> values;
  std::size_t i = 0;
  while (i < rest.size()) {
    if (rest[i] == ' ' || rest[i] == '\t' || rest[i] == '\r') {
      ++i;
      continue;
    }
    double v = 0.0;
    const char* first = rest.data() + i;
    const auto [ptr, ec] = std::from_chars(first, rest.data() + rest.size(), v);
    if (ec != std::errc() || ptr == first || !std::isfinite(v))
      throw Error(where + ": '" +
                  std::string(rest.substr(i, std::min<std::size_t>(20, rest.size() - i))) +
                  "' is not a finite number");
    values.push_back(v);
    i = static_cast<std::size_t>(ptr - rest.data());
  }
  return values;
}

}  // namespace

KittiCalib parse_kitti_calib(std::string_view text, const std::string& source) {
  std::optional<Eigen::Matrix3d> r0_rect;
  std::optional<Pose> tr_velo_to_cam, tr;
  std::size_t line_no = 0;
  while (!text.empty()) {
    ++line_no;
    const auto eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    const auto key_end = line.find_first_of(" \t:");
    if (key_end == std::string_view::npos) continue;
    const std::string key(line.substr(0, key_end));
    std::string_view rest = line.substr(key_end);
    if (!rest.empty() && rest.front() == ':') rest.remove_prefix(1);
    const bool is_rect = key == "R0_rect" || key == "R_rect";
    const bool is_velo = key == "Tr_velo_to_cam" || key == "Tr_velo_cam";
    if (!is_rect && !is_velo && key != "Tr") continue;
    const std::string where = source + ":" + std::to_string(line_no) + " (" + key + ")";
    const std::vector<double> v = parse_numbers(rest, where);
    const std::size_t expected = is_rect ? 9 : 12;
    if (v.size() != expected)
      throw Error(where + ": " + std::to_string(v.size()) + " numbers, expected " +
                  std::to_string(expected));
    if (is_rect) {
      Eigen::Matrix3d r;
      for (int k = 0; k < 9; ++k) r(k / 3, k % 3) = v[static_cast<std::size_t>(k)];
      r0_rect = r;
      continue;
    }
    Pose t = Pose::Identity();
    for (int k = 0; k < 12; ++k) t.matrix()(k / 4, k % 4) = v[static_cast<std::size_t>(k)];
    (is_velo ? tr_velo_to_cam : tr) = t;
  }
  KittiCalib calib;
  if (tr_velo_to_cam) {
    Pose rect = Pose::Identity();
    if (r0_rect) rect.linear() = *r0_rect;
    calib.T_rect_velo = rect * *tr_velo_to_cam;
  } else if (tr) {
    calib.T_rect_velo = *tr;
  } else {
    throw Error(source + ": no Tr_velo_to_cam (or Tr) line: not a KITTI calibration file");
  }
  const Eigen::Matrix3d r = calib.T_rect_velo.linear();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 ||
      r.determinant() <= 0.0)
    throw Error(source + ": the LiDAR-to-camera rotation is not a rotation matrix");
  calib.T_rect_velo.linear() = nearest_rotation(r);
  return calib;
}

KittiCalib read_kitti_calib(const std::filesystem::path& path) {
  const auto bytes = read_file_bytes(path);
  return parse_kitti_calib(
      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path.string());
}

Trajectory camera_to_lidar(const Trajectory& camera, const KittiCalib& calib) {
  const Pose c = calib.T_rect_velo;
  const Pose c_inv = c.inverse(Eigen::Isometry);
  Trajectory lidar;
  for (const auto& sp : camera) lidar.push_back(sp.stamp_s, c_inv * sp.pose * c);
  return lidar;
}

}  // namespace fieldlidar::io
