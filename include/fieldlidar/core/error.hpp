#pragma once
/// \file The project's error type for bad input at a boundary (a file, a parameter).

#include <stdexcept>
#include <string>

namespace fieldlidar {

/// Thrown when input cannot be used: the message names the source (file, field) and the problem.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace fieldlidar
