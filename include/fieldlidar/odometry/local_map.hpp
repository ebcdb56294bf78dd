#pragma once
/// \file seed 002, step e and LOAM's mapping stage: edge and planar points in the world frame in
/// a voxel hash bounded in memory, with the line / plane around a query point.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fieldlidar/core/point_cloud.hpp"
#include "fieldlidar/odometry/lm_solver.hpp"

namespace fieldlidar::odometry {

struct LocalMapConfig {
  /// Side of a voxel; neighbours are searched in the 2 x 2 x 2 voxels nearest the query, so
  /// every map point within voxel_m / 2 of it is seen.
  double voxel_m = 1.0;
  int max_points_per_voxel = 20;     ///< further points in a full voxel are dropped
  double min_point_spacing_m = 0.2;  ///< a point nearer than this to one of its voxel is dropped
  double max_range_m = 60.0;         ///< voxels farther from the robot are removed
  /// Points of a line / plane fit (LOAM: 5). With 5, the range noise tilts each fitted plane and
  /// line at random, and a tilted plane pulls its query along the surface towards the fit points'
  /// centroid. Along an aisle the map's points lie behind the queries (older copies of the same
  /// rings, 4 mm on average): on the simulated greenhouse (VLP-16, 3 cm noise, frames 0-599) every
  /// frame's forward motion came out short, scale 1.0015 (5 points), 1.0003 (8), 1.0000 (10);
  /// without range noise 1.0002 with 5. The 3000-frame drive's ATE: 0.032 m (5), 0.028 (8),
  /// 0.023 (10). The cost: 10 points smooth over the rocks of the simulated terrain (60 frames,
  /// RPE 1.2 cm with 5, 1.4 with 8, 2.1 with 10); 8 made the follow loop's occlusion run never
  /// resume (a fragile case, not understood).
  int neighbours = 10;
  double max_neighbour_distance_m = 1.0;  ///< farthest of them from the query
  double max_plane_distance_m = 0.1;      ///< every fit point within this of the plane
  double min_line_ratio = 3.0;            ///< largest / second eigenvalue of a line fit
  /// Second / largest eigenvalue of a plane fit at least this: points along one scan line fit
  /// any plane through it and would bias the pose.
  double min_plane_spread = 0.25;
  /// RMS distance of the fit points from their plane at most this (m): leaves and clutter are
  /// not planes (0 = off).
  double max_plane_thickness_m = 0.0;
};

/// Points of one kind (edges or planes) in a voxel hash.
class VoxelMap {
 public:
  explicit VoxelMap(const LocalMapConfig& config = {})
      : config_(config),
        inv_voxel_(float(1.0 / config.voxel_m)),
        capacity_(std::size_t(std::max(0, config.max_points_per_voxel))),
        stride_((capacity_ + 3) / 4 * 4) {}
  void insert(std::span<const Eigen::Vector3f> points_world);
  /// Removes the voxels farther than max_range_m from `centre_world`.
  void crop(const Eigen::Vector3d& centre_world);
  void clear();
  /// The `k` nearest points within max_neighbour_distance_m (unsorted), fewer when there are not.
  std::size_t nearest(const Eigen::Vector3f& query, std::vector<Eigen::Vector3f>& out) const;
  std::size_t size() const;
  std::size_t voxel_count() const { return cells_.size(); }
  /// Every point, for saving the map.
  std::vector<Eigen::Vector3f> points() const;

 private:
  struct Key {
    std::int32_t x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct Cell {
    Key key;
    std::uint32_t count = 0;  ///< points held (coordinates_of the voxel)
    /// Bounds of the points held: a search skips the voxel when they are no nearer than its
    /// k-th point so far (no point inside can be nearer, so the result is the same).
    Eigen::Vector3f min, max;
  };
  Key key_of(const Eigen::Vector3f& p) const;
  /// Index of the voxel in cells_, -1 when there is none.
  std::int32_t find(const Key& k) const;
  /// Index of the voxel, created empty when there is none.
  std::int32_t find_or_add(const Key& k);
  /// The open-addressing table (linear probing, power-of-two size) rebuilt from cells_.
  void rebuild_table(std::size_t capacity);
  /// The x of voxel `cell`'s points; y at + stride_, z at + 2 stride_.
  float* coordinates_of(std::size_t cell) { return coords_.data() + 3 * stride_ * cell; }
  const float* coordinates_of(std::size_t cell) const {
    return coords_.data() + 3 * stride_ * cell;
  }
  LocalMapConfig config_;
  float inv_voxel_ = 1.f;     ///< 1 / voxel_m
  std::size_t capacity_ = 0;  ///< max_points_per_voxel
  std::size_t stride_ = 0;    ///< capacity_ rounded up to 4 (whole packets of 4 floats)
  std::vector<Cell> cells_;
  /// Voxel c's points from coords_[3 stride_ c]: stride_ x, then stride_ y, then stride_ z (the
  /// unused slots 0). One flat block, so a neighbour search reads a voxel without following a
  /// pointer, and its distances four points at a time.
  std::vector<float> coords_;
  /// A voxel's key and cells_ index + 1 (0 = empty slot); at most half full. A flat table: a
  /// look-up costs one hash and usually one probe, in one cache line (std::unordered_map cost a
  /// third of the sweep's time).
  struct Slot {
    Key key{0, 0, 0};
    std::int32_t cell = 0;
  };
  std::vector<Slot> table_;
};

/// The local map of LOAM's mapping stage: an edge and a planar voxel map.
class LocalMap {
 public:
  explicit LocalMap(const LocalMapConfig& config = {})
      : config_(config), edges_(config), planes_(config) {}
  const LocalMapConfig& config() const { return config_; }
  void insert(std::span<const Eigen::Vector3f> edges_world,
              std::span<const Eigen::Vector3f> planes_world);
  void crop(const Eigen::Vector3d& centre_world);
  void clear();
  bool empty() const { return edges_.voxel_count() + planes_.voxel_count() == 0; }
  std::size_t size() const { return edges_.size() + planes_.size(); }

  /// The line (edge) or plane of the map around `point_world`; nullopt when the neighbours do not
  /// form one. The returned correspondence has point_lidar unset.
  std::optional<Correspondence> match_edge(const Eigen::Vector3f& point_world) const;
  std::optional<Correspondence> match_plane(const Eigen::Vector3f& point_world) const;

  /// Every map point (edges, then planes), world frame.
  PointCloud to_cloud() const;
  /// A map from a saved cloud: points with intensity 1 are edges, the others planes.
  static LocalMap from_cloud(const PointCloud& cloud, const LocalMapConfig& config = {});

 private:
  LocalMapConfig config_;
  VoxelMap edges_, planes_;
};

}  // namespace fieldlidar::odometry
