#pragma once
// One cell of a CSV file as a finite number, or an error naming the file, line and column: the
// motion streams and the tree truth read their cells so.

#include <cstddef>
#include <filesystem>
#include <string>

namespace fieldlidar::app {

/// `cell` as a finite number; throws fieldlidar::Error "FILE: line N: COLUMN 'cell' is not a
/// number" or "FILE: line N: COLUMN is nan, not a finite number". `plus_sign`: a leading '+' is
/// taken (as other writers put one).
double csv_number(const std::string& cell, const std::filesystem::path& file, std::size_t line,
                  const std::string& column, bool plus_sign = false);

}  // namespace fieldlidar::app
