#pragma once
/// \file A traversability layer as a nav2 / ROS map_server map: a binary PGM (P5) image and its
/// YAML description. Image row 0 is the map's top (largest y); `origin` is the world position of
/// the lower-left pixel's corner.

#include <filesystem>
#include <string>

#include "fieldlidar/core/grid2d.hpp"

namespace fieldlidar::io {

/// Pixel values of the three classes (map_server, negate 0: occupancy = (255 - p) / 255).
inline constexpr unsigned char kNav2Occupied = 0;
inline constexpr unsigned char kNav2Free = 254;
inline constexpr unsigned char kNav2Unknown = 205;

/// map_server reads a pixel p as occupancy occ = (255 - p) / 255: occupied when occ >
/// occupied_thresh, free when occ <= free_thresh, unknown in between (trinary). The unknown grey
/// 205 is occ 0.19608, so free_thresh must stay below it (0.196, as ROS map_saver writes) or
/// unknown cells would load as free.
struct Nav2MapConfig {
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  /// "trinary": cost = 1 - tau above occupied_thresh is occupied (0), every other known cell
  /// free (254); "scale": pixel = round(254 * tau), the cost kept in between.
  std::string mode = "trinary";
};

struct Nav2Map {
  std::string pgm;   ///< the image bytes (P5, maxval 255)
  std::string yaml;  ///< the map_server description naming `image_name`
};

/// Encodes layer `tau_layer` of `grid` (traversability in [0, 1], NaN unknown): cost = 1 - tau,
/// impassable (tau 0) black 0, best white 254, unknown 205. Throws
/// fieldlidar::Error naming the layer when it is missing, the grid is empty or the mode unknown.
Nav2Map encode_nav2_map(const Grid2D& grid, const std::string& tau_layer,
                        const std::string& image_name, const Nav2MapConfig& config = {});

/// Decodes a map_server map (its YAML text and P5 PGM bytes, negate 0 or 1) into layer
/// `tau_layer`: "trinary" occupied -> tau 0, free -> 1, in between -> NaN (unknown); "scale"
/// p / 254 with the unknown grey 205 -> NaN (the inverse of encode_nav2_map). Throws
/// fieldlidar::Error naming `source` and the field on a malformed file.
Grid2D decode_nav2_map(const std::string& yaml, const std::string& pgm, const std::string& tau_layer,
                       const std::string& source);

/// Reads `yaml_path` and the image it names (relative to the YAML's folder).
Grid2D read_nav2_map(const std::filesystem::path& yaml_path, const std::string& tau_layer);

}  // namespace fieldlidar::io
