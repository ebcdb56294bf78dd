#include "support/plan_map.hpp"

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/geotiff.hpp"
#include "fieldlidar/io/nav2_map.hpp"
#include "fieldlidar/terrain/traversability.hpp"

namespace fieldlidar::app {
namespace {

namespace fs = std::filesystem;
namespace L = terrain::layer;

bool same_cells(const GridGeometry& a, const GridGeometry& b) {
  return a.width == b.width && a.height == b.height && a.resolution_m == b.resolution_m &&
         (a.origin_m - b.origin_m).norm() <= 1e-9 * (1.0 + a.origin_m.norm());
}

// A layer written by the traversability command names itself in its band's description.
Grid2D read_layer(const fs::path& file, const std::string& name) {
  std::string description;
  Grid2D layer = io::read_geotiff(file, name, &description);
  if (!description.empty() && description != name)
    throw Error("--map " + file.string() + ": holds the layer '" + description + "', not '" + name +
                "'");
  return layer;
}

PlanMap read_layers(const fs::path& tau_file) {
  PlanMap out{read_layer(tau_file, L::kTraversability), "geotiff", {tau_file}};
  for (const char* name : {L::kImpassable, L::kPoints}) {
    const fs::path f = tau_file.parent_path() / (std::string(name) + ".tif");
    if (!fs::exists(f)) continue;
    const Grid2D layer = read_layer(f, name);
    if (!same_cells(layer.geometry(), out.grid.geometry()))
      throw Error("--map " + f.string() + ": its cells differ from " + tau_file.string() + "'s");
    const auto src = layer.layer(name);
    auto dst = out.grid.add_layer(name, 0.0f);
    std::copy(src.begin(), src.end(), dst.begin());
    out.files.push_back(f);
  }
  return out;
}

PlanMap read_nav2(const fs::path& yaml) {
  return {io::read_nav2_map(yaml, L::kTraversability), "nav2", {yaml}};
}

}  // namespace

PlanMap read_plan_map(const std::string& map) {
  const fs::path p(map);
  if (!fs::exists(p)) throw Error("--map " + map + ": no such file or folder");
  if (fs::is_directory(p)) {
    if (fs::exists(p / "traversability.yaml")) return read_nav2(p / "traversability.yaml");
    if (fs::exists(p / "traversability.tif")) return read_layers(p / "traversability.tif");
    for (const auto& e : fs::directory_iterator(p))
      if (e.path().extension() == ".yaml") return read_nav2(e.path());
    throw Error("--map " + map + ": no nav2 map (.yaml) nor traversability.tif in the folder");
  }
  const std::string ext = p.extension().string();
  if (ext == ".tif" || ext == ".tiff") return read_layers(p);
  return read_nav2(p);
}

}  // namespace fieldlidar::app
