#include "fieldlidar/io/kitti_tracking_labels.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {

bool KittiObject::contains(const Eigen::Vector3d& p, double margin_m) const {
  if (!has_box()) return false;
  const Eigen::Vector3d d = p - bottom_rect_m;
  // Box axes: length along the rotated x, width along the rotated z (R_y(ry)).
  const double c = std::cos(ry_rad), s = std::sin(ry_rad);
  const double along_l = c * d.x() - s * d.z();
  const double along_w = s * d.x() + c * d.z();
  return std::abs(along_l) <= l_m / 2 + margin_m && std::abs(along_w) <= w_m / 2 + margin_m &&
         d.y() <= margin_m && d.y() >= -h_m - margin_m;
}

std::vector<KittiObject> parse_kitti_tracking_labels(std::string_view text,
                                                     const std::string& source) {
  std::vector<KittiObject> out;
  std::istringstream in{std::string(text)};
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream ls(line);
    KittiObject o;
    double alpha = 0, bbox[4], x = 0, y = 0, z = 0;
    ls >> o.frame >> o.track_id >> o.type >> o.truncated >> o.occluded >> alpha >> bbox[0] >>
        bbox[1] >> bbox[2] >> bbox[3] >> o.h_m >> o.w_m >> o.l_m >> x >> y >> z >> o.ry_rad;
    if (ls.fail())
      throw Error(source + ": line " + std::to_string(n) +
                  ": expected 17 fields `frame track_id type truncated occluded alpha bbox(4) h w "
                  "l x y z ry`, got '" +
                  line + "'");
    // What the columns allow but no annotation can be: no sweep has a negative index, and a box
    // of size <= 0 contains no point (its person would count as missed). DontCare rows carry
    // -1 sizes by convention.
    const std::string at = source + ": line " + std::to_string(n) + ": ";
    if (o.frame < 0) throw Error(at + "frame " + std::to_string(o.frame) + " is negative");
    if (o.type != "DontCare" && !(o.h_m > 0 && o.w_m > 0 && o.l_m > 0)) {
      std::ostringstream m;
      m << at << o.type << " box size h " << o.h_m << " w " << o.w_m << " l " << o.l_m
        << " m is not positive";
      throw Error(m.str());
    }
    o.bottom_rect_m = Eigen::Vector3d(x, y, z);
    out.push_back(std::move(o));
  }
  return out;
}

std::vector<KittiObject> read_kitti_tracking_labels(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_kitti_tracking_labels(ss.str(), path.string());
}

}  // namespace fieldlidar::io
