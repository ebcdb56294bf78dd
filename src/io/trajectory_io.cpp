#include "fieldlidar/io/trajectory_io.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::io {

namespace {

std::string read_text(const std::filesystem::path& path) {
  const auto bytes = read_file_bytes(path);
  return std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

/// Calls `on_line(line_number, numbers)` for every non-empty, non-comment line.
template <typename OnLine>
void for_each_number_line(std::string_view text, const std::string& source, OnLine on_line) {
  std::size_t line_no = 0;
  std::vector<double> values;
  while (!text.empty()) {
    ++line_no;
    const auto eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    values.clear();
    std::size_t i = 0;
    while (i < line.size()) {
      const char c = line[i];
      if (c == ' ' || c == '\t' || c == '\r' || c == ',') {
        ++i;
        continue;
      }
      if (c == '#') break;  // comment to the end of the line
      double v = 0.0;
      const char* first = line.data() + i;
      const char* last = line.data() + line.size();
      if (c == '+') ++first;  // from_chars does not take a leading '+'
      const auto [ptr, ec] = std::from_chars(first, last, v);
      if (ec != std::errc() || ptr == first)
        throw Error(source + ":" + std::to_string(line_no) + ": '" +
                    std::string(line.substr(i, std::min<std::size_t>(20, line.size() - i))) +
                    "' is not a number");
      if (!std::isfinite(v))
        throw Error(source + ":" + std::to_string(line_no) + ": value " +
                    std::to_string(values.size() + 1) + " is NaN or infinite");
      values.push_back(v);
      i = static_cast<std::size_t>(ptr - line.data());
      if (i < line.size() && !(line[i] == ' ' || line[i] == '\t' || line[i] == '\r' ||
                               line[i] == ',' || line[i] == '#'))
        throw Error(source + ":" + std::to_string(line_no) + ": malformed number near column " +
                    std::to_string(i + 1));
    }
    if (!values.empty()) on_line(line_no, values);
  }
}

void push_checked(Trajectory& traj, double stamp_s, const Pose& pose, const std::string& source,
                  std::size_t line_no) {
  try {
    traj.push_back(stamp_s, pose);
  } catch (const std::invalid_argument&) {
    throw Error(source + ":" + std::to_string(line_no) + ": time " + std::to_string(stamp_s) +
                " s is not after the previous pose's time");
  }
}

std::string format_g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.12g", v);
  return buf;
}

void write_text(const std::filesystem::path& path, const std::string& text,
                const WriteOptions& options) {
  write_file_atomic(path, text.data(), text.size(), options.overwrite);
}

}  // namespace

Trajectory parse_kitti_poses(std::string_view text, const std::string& source,
                             const std::vector<double>& stamps_s) {
  Trajectory traj;
  std::size_t index = 0;
  for_each_number_line(text, source, [&](std::size_t line_no, const std::vector<double>& v) {
    if (v.size() != 12)
      throw Error(source + ":" + std::to_string(line_no) + ": KITTI pose line has " +
                  std::to_string(v.size()) + " numbers, expected 12 (3x4 row-major)");
    Pose pose = Pose::Identity();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = v[4 * r + c];
    const Eigen::Matrix3d R = pose.linear();
    // A 3x4 KITTI pose printed with ~7 significant digits is orthonormal to ~1e-6.
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-3 ||
        R.determinant() < 0.0)
      throw Error(source + ":" + std::to_string(line_no) +
                  ": the 3x3 block is not a rotation matrix");
    if (!stamps_s.empty() && index >= stamps_s.size())
      throw Error(source + ": more poses than the " + std::to_string(stamps_s.size()) +
                  " times given");
    const double t = stamps_s.empty() ? static_cast<double>(index) : stamps_s[index];
    push_checked(traj, t, pose, source, line_no);
    ++index;
  });
  if (!stamps_s.empty() && index != stamps_s.size())
    throw Error(source + ": has " + std::to_string(index) + " poses but " +
                std::to_string(stamps_s.size()) + " times were given");
  return traj;
}

std::vector<double> parse_kitti_times(std::string_view text, const std::string& source) {
  std::vector<double> times;
  for_each_number_line(text, source, [&](std::size_t line_no, const std::vector<double>& v) {
    if (v.size() != 1)
      throw Error(source + ":" + std::to_string(line_no) + ": KITTI times line has " +
                  std::to_string(v.size()) + " numbers, expected 1");
    times.push_back(v[0]);
  });
  return times;
}

std::vector<double> read_kitti_times(const std::filesystem::path& path) {
  return parse_kitti_times(read_text(path), path.string());
}

Trajectory read_kitti_poses(const std::filesystem::path& path, const std::filesystem::path& times) {
  std::vector<double> stamps;
  if (!times.empty()) {
    stamps = read_kitti_times(times);
    if (stamps.empty()) throw Error(times.string() + ": no times in the file");
  }
  return parse_kitti_poses(read_text(path), path.string(), stamps);
}

void write_kitti_poses(const std::filesystem::path& path, const Trajectory& trajectory,
                       const WriteOptions& options) {
  std::string text;
  for (const auto& sp : trajectory) {
    const auto& m = sp.pose.matrix();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        text += format_g(m(r, c));
        text += (r == 2 && c == 3) ? '\n' : ' ';
      }
  }
  write_text(path, text, options);
}

void write_kitti_times(const std::filesystem::path& path, const Trajectory& trajectory,
                       const WriteOptions& options) {
  std::string text;
  for (const auto& sp : trajectory) {
    char buf[40];
    std::snprintf(buf, sizeof(buf), "%.9f\n", sp.stamp_s);
    text += buf;
  }
  write_text(path, text, options);
}

Trajectory parse_tum(std::string_view text, const std::string& source) {
  Trajectory traj;
  for_each_number_line(text, source, [&](std::size_t line_no, const std::vector<double>& v) {
    if (v.size() != 8)
      throw Error(source + ":" + std::to_string(line_no) + ": TUM line has " +
                  std::to_string(v.size()) + " numbers, expected 8 (t x y z qx qy qz qw)");
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    const double norm = q.norm();
    if (!(norm > 1e-6))
      throw Error(source + ":" + std::to_string(line_no) + ": quaternion has zero length");
    q.coeffs() /= norm;
    Pose pose = Pose::Identity();
    pose.linear() = q.toRotationMatrix();
    pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    push_checked(traj, v[0], pose, source, line_no);
  });
  return traj;
}

Trajectory read_tum(const std::filesystem::path& path) {
  return parse_tum(read_text(path), path.string());
}

void write_tum(const std::filesystem::path& path, const Trajectory& trajectory,
               const WriteOptions& options) {
  std::string text = "# t x y z qx qy qz qw\n";
  for (const auto& sp : trajectory) {
    const Eigen::Quaterniond q(sp.pose.rotation());
    const Eigen::Vector3d t = sp.pose.translation();
    char buf[256];
    std::snprintf(buf, sizeof(buf), "%.9f %.12g %.12g %.12g %.12g %.12g %.12g %.12g\n", sp.stamp_s,
                  t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
    text += buf;
  }
  write_text(path, text, options);
}

}  // namespace fieldlidar::io
