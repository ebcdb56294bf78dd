#pragma once
/// \file The geometry of a multi-beam LiDAR: beam angles, resolution, range limits, mounting.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace fieldlidar {

/// A spinning multi-beam LiDAR, a 2D laser tilted through elevations (tilting_2d()) or a fixed
/// planar 2D laser (laser_2d()).
///
/// Ring i is the beam with the i-th smallest elevation: ring 0 looks lowest. Angles in radians,
/// elevation positive above the sensor's x-y plane, azimuth counter-clockwise from +x.
struct SensorModel {
  /// kTilting2D and kPlanar2D scan a fan centred on +x, right to left (a planar laser is a
  /// tilting one with a single plane at elevation 0).
  enum class Kind { kSpinning, kTilting2D, kPlanar2D };

  std::string name;
  Kind kind = Kind::kSpinning;
  std::vector<double> beam_altitudes_rad;        ///< per ring, ascending
  std::vector<double> beam_azimuth_offsets_rad;  ///< per ring, added to the column azimuth
  int columns = 1800;  ///< horizontal samples per revolution (or per 2D scan)
  double horizontal_fov_rad = 6.283185307179586;  ///< 2*pi for a full spin
  double rotation_rate_hz = 10.0;  ///< sweeps per second (tilt cycles for kTilting2D)
  double min_range_m = 0.5;
  double max_range_m = 100.0;
  double range_accuracy_m = 0.02;     ///< 1-sigma range noise from the data sheet
  double beam_origin_offset_m = 0.0;  ///< distance from the rotation axis to the beam origin
  double mounting_height_m = 0.0;     ///< height of the sensor origin above the ground, 0 = unknown

  std::size_t rings() const { return beam_altitudes_rad.size(); }
  /// Horizontal angle between two columns.
  double horizontal_resolution_rad() const { return horizontal_fov_rad / columns; }
  double min_altitude_rad() const;
  double max_altitude_rad() const;
  /// Range at which the lowest beam meets level ground `height_m` below the sensor (the blind
  /// radius: no ground return nearer); infinity when no beam looks down.
  double ground_reach_m(double height_m) const;
  /// Mean spacing of the beam elevations (vertical resolution of a uniform range image).
  double vertical_resolution_rad() const;
  /// Ring whose elevation is nearest to `altitude_rad` (works for non-uniform beam tables).
  std::size_t nearest_ring(double altitude_rad) const;
  /// Time for one sweep.
  double sweep_period_s() const { return 1.0 / rotation_rate_hz; }

  /// Throws std::invalid_argument naming the offending field when the model is not usable.
  void validate() const;

  // Presets with the published beam tables.
  static SensorModel vlp16();
  static SensorModel vlp32c();
  static SensorModel hdl32e();
  static SensorModel hdl64e();
  static SensorModel os1_64();
  static SensorModel os1_128();
  static SensorModel os2_128();
  /// A 2D scanner (`columns` samples over `scan_fov_rad`) nodding through `planes` elevations
  /// evenly spread over [min_tilt_rad, max_tilt_rad], as used by the forest seed.
  static SensorModel tilting_2d(int planes = 60, double min_tilt_rad = -0.35,
                                double max_tilt_rad = 0.7, int columns = 1081,
                                double scan_fov_rad = 4.71238898038469);
  /// A fixed planar 2D laser scanner (one ring at elevation 0): `columns` samples over
  /// `scan_fov_rad` centred on +x. The default is a leg-height safety laser class: 270 deg at
  /// 0.3516 deg steps (the spacing of the legs_2d bags' laser, which the shipped 2D leg classifier
  /// learned), 10 scans/s, 0.05-30 m, 1 cm noise.
  static SensorModel laser_2d(int columns = 768, double scan_fov_rad = 4.71238898038469,
                              double rate_hz = 10.0, double max_range_m = 30.0);
  /// A sensor described by its beam elevations (any order; sorted ascending into rings).
  static SensorModel from_beam_angles(std::string name, std::vector<double> altitudes_rad,
                                      int columns, double rotation_rate_hz = 10.0,
                                      double min_range_m = 0.5, double max_range_m = 100.0);
  /// Preset by name: vlp16, vlp32c, hdl32e, hdl64e, os1-64, os1-128, os2-128, tilting2d,
  /// laser2d.
  static std::optional<SensorModel> preset(const std::string& name);
  static std::vector<std::string> preset_names();
};

}  // namespace fieldlidar
