#pragma once
// The rows of a CSV file the tool wrote, as text fields (no quoting: the tool's logs have none).

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fieldlidar::test {

/// Rows of the CSV file `p` after its header line, each as its comma-separated fields.
inline std::vector<std::vector<std::string>> csv_text_rows(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) f.push_back(cell);
    rows.push_back(std::move(f));
  }
  return rows;
}

}  // namespace fieldlidar::test
