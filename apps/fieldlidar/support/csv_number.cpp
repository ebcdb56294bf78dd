#include "support/csv_number.hpp"

#include <charconv>
#include <cmath>

#include <fmt/core.h>

#include "fieldlidar/core/error.hpp"

namespace fieldlidar::app {

double csv_number(const std::string& cell, const std::filesystem::path& file, std::size_t line,
                  const std::string& column, bool plus_sign) {
  // from_chars takes no leading '+'.
  const char* first = cell.data() + (plus_sign && cell.size() > 1 && cell[0] == '+');
  double v = 0;
  const auto [end, ec] = std::from_chars(first, cell.data() + cell.size(), v);
  if (ec != std::errc() || end != cell.data() + cell.size() || cell.empty())
    throw Error(
        fmt::format("{}: line {}: {} '{}' is not a number", file.string(), line, column, cell));
  if (!std::isfinite(v))
    throw Error(fmt::format("{}: line {}: {} is {}, not a finite number", file.string(), line,
                            column, cell));
  return v;
}

}  // namespace fieldlidar::app
