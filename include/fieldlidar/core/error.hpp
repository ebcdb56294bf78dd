#pragma once
/// \file The project's error type for bad input at a boundary (a file, a parameter).

#include <cstdio>
#include <stdexcept>
#include <string>

namespace fieldlidar {

/// Thrown when input cannot be used: the message names the source (file, field) and the problem.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A number as an Error message shows it: printf's %g ("1e+300", "0.5"), not std::to_string's
/// six decimals or a 309-digit DBL_MAX.
inline std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace fieldlidar
