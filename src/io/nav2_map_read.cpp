// Reading a nav2 / ROS map_server map (YAML + P5 PGM) back into a grid layer.

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "fieldlidar/core/error.hpp"
#include "fieldlidar/io/nav2_map.hpp"

namespace fieldlidar::io {
namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\"'");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r\"'");
  return s.substr(a, b - a + 1);
}

double number(const std::map<std::string, std::string>& kv, const std::string& key,
              const std::string& source, double fallback, bool required) {
  const auto it = kv.find(key);
  if (it == kv.end()) {
    if (required) throw Error(source + ": no '" + key + "'");
    return fallback;
  }
  try {
    std::size_t used = 0;
    const double v = std::stod(it->second, &used);
    if (used == it->second.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw Error(source + ": " + key + " '" + it->second + "' is not a number");
}

// The next header token of a PGM (comments skipped).
std::string pgm_token(std::istringstream& in) {
  std::string t;
  while (in >> t) {
    if (t[0] != '#') return t;
    std::string rest;
    std::getline(in, rest);
  }
  return "";
}

}  // namespace

Grid2D decode_nav2_map(const std::string& yaml, const std::string& pgm,
                       const std::string& tau_layer, const std::string& source) {
  std::map<std::string, std::string> kv;
  std::istringstream lines(yaml);
  for (std::string line; std::getline(lines, line);) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    kv[trim(line.substr(0, colon))] = trim(line.substr(colon + 1));
  }
  const double res = number(kv, "resolution", source, 0, true);
  if (!(res > 0.0 && res <= 1000.0)) throw Error(source + ": resolution " + kv["resolution"]);
  const double negate_value = number(kv, "negate", source, 0, false);
  if (negate_value != 0.0 && negate_value != 1.0)
    throw Error(source + ": negate " + kv["negate"] + " must be 0 or 1");
  const bool negate = negate_value == 1.0;
  const double occupied = number(kv, "occupied_thresh", source, 0.65, false);
  const double free = number(kv, "free_thresh", source, 0.196, false);
  // A threshold as written, or its default when the YAML has none.
  const auto shown = [&kv](const std::string& key, double v) {
    if (const auto it = kv.find(key); it != kv.end()) return it->second;
    std::ostringstream s;
    s << v << " (default)";
    return s.str();
  };
  if (!(occupied >= 0.0 && occupied <= 1.0))
    throw Error(source + ": occupied_thresh " + shown("occupied_thresh", occupied) +
                " must be in [0, 1]");
  if (!(free >= 0.0 && free <= 1.0))
    throw Error(source + ": free_thresh " + shown("free_thresh", free) + " must be in [0, 1]");
  // Equal or crossed thresholds leave no band between free and occupied: the map would not
  // read the same in map_server.
  if (!(occupied > free))
    throw Error(source + ": occupied_thresh " + shown("occupied_thresh", occupied) +
                " must be above free_thresh " + shown("free_thresh", free));
  const std::string mode = kv.count("mode") ? kv["mode"] : "trinary";
  if (mode != "trinary" && mode != "scale")
    throw Error(source + ": mode '" + mode + "' is not trinary or scale");
  std::string origin = kv.count("origin") ? kv["origin"] : "[0, 0, 0]";
  for (char& ch : origin)
    if (ch == '[' || ch == ']' || ch == ',') ch = ' ';
  std::istringstream os(origin);
  double ox = 0, oy = 0;
  if (!(os >> ox >> oy)) throw Error(source + ": origin '" + kv["origin"] + "'");

  std::istringstream in(pgm);
  const std::string magic = pgm_token(in);
  if (magic != "P5")
    throw Error(source + ": image is not a binary PGM (P5), magic '" + magic + "'");
  int w = 0, h = 0, maxval = 0;
  try {
    w = std::stoi(pgm_token(in));
    h = std::stoi(pgm_token(in));
    maxval = std::stoi(pgm_token(in));
  } catch (const std::exception&) {
    throw Error(source + ": malformed PGM header");
  }
  if (w <= 0 || h <= 0 || w > 100000 || h > 100000 || maxval != 255)
    throw Error(source + ": PGM " + std::to_string(w) + " x " + std::to_string(h) + ", maxval " +
                std::to_string(maxval) + " (need 8-bit, 1..100000 pixels a side)");
  const std::size_t start = std::size_t(in.tellg()) + 1;  // one whitespace after maxval
  if (pgm.size() < start + std::size_t(w) * h)
    throw Error(source + ": PGM truncated (" + std::to_string(pgm.size()) + " bytes)");

  GridGeometry g;
  g.resolution_m = res;
  g.origin_m = {ox, oy};
  g.width = w;
  g.height = h;
  Grid2D grid(g);
  auto tau = grid.add_layer(tau_layer, std::numeric_limits<float>::quiet_NaN());
  for (int row = 0; row < h; ++row) {
    const int iy = h - 1 - row;
    for (int ix = 0; ix < w; ++ix) {
      int p = static_cast<unsigned char>(pgm[start + std::size_t(row) * w + ix]);
      if (negate) p = 255 - p;
      float& t = tau[g.linear_index(ix, iy)];
      if (mode == "scale") {
        if (p != kNav2Unknown) t = float(std::min(254, p)) / 254.0f;
        continue;
      }
      const double occ = (255.0 - p) / 255.0;
      if (occ > occupied)
        t = 0.0f;
      else if (occ <= free)
        t = 1.0f;
    }
  }
  return grid;
}

Grid2D read_nav2_map(const std::filesystem::path& yaml_path, const std::string& tau_layer) {
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    if (!f) throw Error(p.string() + ": cannot open");
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
  };
  const std::string yaml = slurp(yaml_path);
  std::string image;
  std::istringstream lines(yaml);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("image:", 0) == 0) image = trim(line.substr(6));
  if (image.empty()) throw Error(yaml_path.string() + ": no 'image'");
  std::filesystem::path img(image);
  if (img.is_relative()) img = yaml_path.parent_path() / img;
  return decode_nav2_map(yaml, slurp(img), tau_layer, yaml_path.string());
}

}  // namespace fieldlidar::io
