// ROS1 wire-format decoders: little-endian, strings and arrays prefixed by a uint32 length.
#include <cmath>
#include <cstring>
#include <limits>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/rosbag_reader.hpp"

namespace fieldlidar::io {
namespace {

class WireReader {
 public:
  WireReader(std::span<const std::uint8_t> bytes, const char* type) : b_(bytes), type_(type) {}

  template <class T>
  T read() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::uint32_t length(std::size_t element_bytes) {
    const auto n = read<std::uint32_t>();
    if (element_bytes && std::size_t(n) > (b_.size() - pos_) / element_bytes)
      fail("an array of " + std::to_string(n) + " elements runs past the end");
    return n;
  }
  std::string string() {
    const auto n = length(1);
    std::string s(reinterpret_cast<const char*>(b_.data() + pos_), n);
    pos_ += n;
    return s;
  }
  std::span<const std::uint8_t> bytes(std::size_t n) {
    need(n);
    auto s = b_.subspan(pos_, n);
    pos_ += n;
    return s;
  }
  void skip(std::size_t n) { need(n), pos_ += n; }
  /// std_msgs/Header: seq, stamp (sec, nsec), frame_id. Returns the stamp in s.
  double header(std::string* frame_id = nullptr) {
    read<std::uint32_t>();
    const auto sec = read<std::uint32_t>();
    const auto nsec = read<std::uint32_t>();
    std::string f = string();
    if (frame_id) *frame_id = std::move(f);
    return double(sec) + double(nsec) * 1e-9;
  }
  Pose pose() {
    double v[7];
    for (double& x : v) x = read<double>();
    Pose p = Pose::Identity();
    p.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (!(q.norm() > 1e-9) || !std::isfinite(q.norm())) q = Eigen::Quaterniond::Identity();
    p.linear() = q.normalized().toRotationMatrix();
    return p;
  }
  Eigen::Vector3d vector3() {
    Eigen::Vector3d v;
    for (int k = 0; k < 3; ++k) v[k] = read<double>();
    return v;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(std::string(type_) + " message (" + std::to_string(b_.size()) + " bytes): " + what);
  }

 private:
  void need(std::size_t n) const {
    if (n > b_.size() - pos_) fail("truncated at byte " + std::to_string(pos_));
  }
  std::span<const std::uint8_t> b_;
  std::size_t pos_ = 0;
  const char* type_;
};

double read_scalar(const std::uint8_t* p, std::uint8_t datatype) {
  switch (datatype) {
    case 1:
      return double(*reinterpret_cast<const std::int8_t*>(p));
    case 2:
      return double(*p);
    case 3: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case 4: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case 5: {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case 6: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case 7: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case 8: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
    default:
      return 0;
  }
}
std::size_t scalar_bytes(std::uint8_t datatype) {
  constexpr std::size_t sizes[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
  return datatype <= 8 ? sizes[datatype] : 0;
}

}  // namespace

PointCloud parse_laser_scan(std::span<const std::uint8_t> bytes) {
  WireReader r(bytes, "sensor_msgs/LaserScan");
  PointCloud cloud;
  cloud.stamp_s = r.header();
  const float angle_min = r.read<float>();
  r.read<float>();  // angle_max follows from the count
  const float angle_increment = r.read<float>();
  const float time_increment = r.read<float>();
  r.read<float>();  // scan_time
  const float range_min = r.read<float>();
  const float range_max = r.read<float>();
  const std::uint32_t n = r.length(4);
  std::vector<float> ranges(n);
  for (auto& v : ranges) v = r.read<float>();
  const std::uint32_t ni = r.length(4);
  std::vector<float> intensities(ni);
  for (auto& v : intensities) v = r.read<float>();
  if (!std::isfinite(angle_min) || !std::isfinite(angle_increment))
    r.fail("angle_min/angle_increment are not finite");
  cloud.reserve(n);
  cloud.fields.ring = cloud.fields.time = true;
  cloud.fields.intensity = ni == n && n > 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const float rng = ranges[i];
    if (!std::isfinite(rng) || rng < range_min || rng > range_max || rng <= 0) continue;
    const double a = double(angle_min) + double(i) * double(angle_increment);
    Point p;
    p.x = float(rng * std::cos(a));
    p.y = float(rng * std::sin(a));
    p.z = 0;
    p.ring = 0;
    p.time = std::isfinite(time_increment) ? float(i) * time_increment : 0.f;
    p.intensity = cloud.fields.intensity ? intensities[i] : 0.f;
    cloud.push_back(p);
  }
  cloud.width = std::uint32_t(cloud.size());
  cloud.height = 1;
  return cloud;
}

PointCloud parse_point_cloud2(std::span<const std::uint8_t> bytes) {
  WireReader r(bytes, "sensor_msgs/PointCloud2");
  PointCloud cloud;
  cloud.stamp_s = r.header();
  const std::uint32_t height = r.read<std::uint32_t>();
  const std::uint32_t width = r.read<std::uint32_t>();
  struct Field {
    std::uint32_t offset = 0;
    std::uint8_t type = 0;
    bool present = false;
  };
  Field fx, fy, fz, fi, fr, ft;
  std::string time_name;
  const std::uint32_t nfields = r.length(9);
  for (std::uint32_t k = 0; k < nfields; ++k) {
    const std::string name = r.string();
    Field f;
    f.offset = r.read<std::uint32_t>();
    f.type = r.read<std::uint8_t>();
    r.read<std::uint32_t>();  // count
    f.present = scalar_bytes(f.type) > 0;
    if (name == "x")
      fx = f;
    else if (name == "y")
      fy = f;
    else if (name == "z")
      fz = f;
    else if (name == "intensity" || (name == "reflectivity" && !fi.present))
      fi = f;
    else if (name == "ring" || name == "channel")
      fr = f;
    else if (name == "time" || name == "t" || name == "timestamp")
      ft = f, time_name = name;
  }
  const bool big_endian = r.read<std::uint8_t>() != 0;
  const std::uint32_t point_step = r.read<std::uint32_t>();
  const std::uint32_t row_step = r.read<std::uint32_t>();
  const std::uint32_t data_len = r.length(1);
  const auto data = r.bytes(data_len);
  if (!fx.present || !fy.present || !fz.present) r.fail("fields x, y and z are required");
  if (big_endian) r.fail("big-endian point data is not supported");
  for (const Field* f : {&fx, &fy, &fz, &fi, &fr, &ft})
    if (f->present && std::size_t(f->offset) + scalar_bytes(f->type) > point_step)
      r.fail("a field lies outside point_step = " + std::to_string(point_step));
  const std::uint64_t n = std::uint64_t(width) * height;
  if (n > 0 && (std::uint64_t(row_step) < std::uint64_t(width) * point_step ||
                std::uint64_t(row_step) * height > data.size()))
    r.fail("data holds " + std::to_string(data.size()) + " bytes, too few for " +
           std::to_string(width) + " x " + std::to_string(height) + " points of " +
           std::to_string(point_step) + " bytes");
  const bool organized = height > 1;
  cloud.fields.intensity = fi.present;
  cloud.fields.ring = fr.present;
  cloud.fields.time = ft.present;
  cloud.reserve(std::size_t(n));
  const bool integer_time = ft.present && ft.type != 7 && ft.type != 8;
  for (std::uint32_t row = 0; row < height; ++row)
    for (std::uint32_t col = 0; col < width; ++col) {
      const std::uint8_t* p =
          data.data() + std::size_t(row) * row_step + std::size_t(col) * point_step;
      Point q;
      q.x = float(read_scalar(p + fx.offset, fx.type));
      q.y = float(read_scalar(p + fy.offset, fy.type));
      q.z = float(read_scalar(p + fz.offset, fz.type));
      const bool finite = std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
      if (!finite) {
        if (!organized) continue;
        q.x = q.y = q.z = 0.f;  // keep the grid: all-zero marks "no return"
      }
      if (fi.present) q.intensity = float(read_scalar(p + fi.offset, fi.type));
      if (fr.present) {
        const double ring = read_scalar(p + fr.offset, fr.type);
        q.ring = ring >= 0 && ring < Point::kNoRing ? std::uint16_t(ring) : Point::kNoRing;
      }
      if (ft.present) {
        double t = read_scalar(p + ft.offset, ft.type);
        if (integer_time)
          t *= 1e-9;  // Ouster driver: uint32 ns offset
        else if (t > 1e6)
          t -= cloud.stamp_s;  // absolute stamps (s)
        q.time = std::isfinite(t) ? float(t) : 0.f;
      }
      cloud.push_back(q);
    }
  cloud.width = organized ? width : std::uint32_t(cloud.size());
  cloud.height = organized ? height : 1;
  (void)time_name;
  return cloud;
}

ImuSample parse_imu(std::span<const std::uint8_t> bytes) {
  WireReader r(bytes, "sensor_msgs/Imu");
  ImuSample s;
  s.stamp_s = r.header();
  r.skip(4 * 8 + 9 * 8);  // orientation quaternion and its covariance
  s.gyro_rad_s = r.vector3();
  r.skip(9 * 8);
  s.accel_m_s2 = r.vector3();
  r.skip(9 * 8);
  return s;
}

OdometrySample parse_odometry(std::span<const std::uint8_t> bytes) {
  WireReader r(bytes, "nav_msgs/Odometry");
  OdometrySample s;
  s.stamp_s = r.header();
  s.child_frame_id = r.string();
  s.pose = r.pose();
  r.skip(36 * 8);
  s.linear_m_s = r.vector3();
  s.angular_rad_s = r.vector3();
  r.skip(36 * 8);
  return s;
}

OdometrySample parse_twist_stamped(std::span<const std::uint8_t> bytes) {
  WireReader r(bytes, "geometry_msgs/TwistStamped");
  OdometrySample s;
  s.stamp_s = r.header();
  s.linear_m_s = r.vector3();
  s.angular_rad_s = r.vector3();
  return s;
}

std::vector<TransformSample> parse_tf_message(std::span<const std::uint8_t> bytes) {
  WireReader r(bytes, "tf2_msgs/TFMessage");
  // geometry_msgs/TransformStamped: header (>= 16 bytes), child_frame_id (>= 4), 7 doubles.
  const std::uint32_t n = r.length(16 + 4 + 56);
  std::vector<TransformSample> out(n);
  for (auto& t : out) {
    t.stamp_s = r.header(&t.parent);
    t.child = r.string();
    t.T_parent_child = r.pose();
  }
  return out;
}

PoseArraySample parse_pose_array(std::span<const std::uint8_t> bytes) {
  WireReader r(bytes, "geometry_msgs/PoseArray");
  PoseArraySample s;
  s.stamp_s = r.header(&s.frame_id);
  const std::uint32_t n = r.length(56);
  s.poses.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) s.poses.push_back(r.pose());
  return s;
}

PersonAnnotation parse_leg_tracker_person(std::span<const std::uint8_t> bytes) {
  WireReader r(bytes, "leg_tracker/Person");
  PersonAnnotation a;
  a.pose = r.pose();
  a.id = r.read<std::uint32_t>();
  return a;
}

}  // namespace fieldlidar::io
