#include "support/motion_csv.hpp"

#include <fstream>
#include <sstream>
#include <string>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"
#include "support/csv_number.hpp"

namespace fieldlidar::app {

namespace {

namespace fs = std::filesystem;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    const auto first = cell.find_first_not_of(" \t\r");
    const auto last = cell.find_last_not_of(" \t\r");
    cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
  }
  return cells;
}

/// Rows of finite numbers of a CSV file with a header line; a cell that is not one is an error
/// naming the line and the header's name of its column.
std::vector<std::vector<double>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw Error(path.string() + ": cannot open");
  std::vector<std::vector<double>> rows;
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> names = split(line);
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::vector<double> row;
    for (const auto& cell : split(line)) {
      const std::size_t column = row.size();
      const std::string name =
          column < names.size() ? names[column] : fmt::format("column {}", column + 1);
      row.push_back(csv_number(cell, path, std::size_t(n), name, true));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

std::vector<ImuSample> read_imu_csv(const fs::path& path) {
  std::vector<ImuSample> out;
  for (const auto& r : read_csv(path)) {
    if (r.size() < 7) throw Error(path.string() + ": an IMU row needs 7 columns");
    out.push_back({r[0], {r[1], r[2], r[3]}, {r[4], r[5], r[6]}});
  }
  return out;
}

std::vector<odometry::WheelSample> read_wheels_csv(const fs::path& path) {
  std::vector<odometry::WheelSample> out;
  for (const auto& r : read_csv(path)) {
    if (r.size() >= 7)
      out.push_back({r[0], r[5], r[6]});
    else if (r.size() == 3)
      out.push_back({r[0], r[1], r[2]});
    else
      throw Error(path.string() + ": a wheel row needs 3 or 10 columns");
  }
  return out;
}

}  // namespace fieldlidar::app
