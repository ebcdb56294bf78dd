#include "support/option_checks.hpp"

#include <charconv>
#include <cmath>
#include <limits>

#include <fmt/core.h>

namespace fieldlidar::app {

namespace {

std::string num(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:g}", v);
}

bool parse_real(const std::string& s, double& v) {
  const char* end = s.data() + s.size();
  const auto [p, ec] = std::from_chars(s.data(), end, v);
  return ec == std::errc() && p == end && std::isfinite(v);
}

}  // namespace

CLI::Validator real_in(double lo, double hi) {
  std::string range;
  if (std::isinf(hi))
    range = ">= " + num(lo);
  else if (std::isinf(lo))
    range = "<= " + num(hi);
  else
    range = "in [" + num(lo) + ", " + num(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& s) -> std::string {
        double v = 0;
        if (!parse_real(s, v)) return "must be a number " + range + ", got '" + s + "'";
        if (v < lo || v > hi) return "must be " + range + ", got " + s;
        return {};
      },
      range);
}

CLI::Validator real_above(double lo, double hi) {
  const std::string range = hi >= 1e300 ? "> " + num(lo) : "in (" + num(lo) + ", " + num(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& s) -> std::string {
        double v = 0;
        if (!parse_real(s, v)) return "must be a number " + range + ", got '" + s + "'";
        if (!(v > lo) || v > hi) return "must be " + range + ", got " + s;
        return {};
      },
      range);
}

CLI::Validator real_finite() {
  const std::string range = "a finite number";
  return CLI::Validator(
      [range](std::string& s) -> std::string {
        double v = 0;
        if (!parse_real(s, v)) return "must be " + range + ", got '" + s + "'";
        return {};
      },
      range);
}

CLI::Validator whole_in(long long lo, long long hi) {
  const std::string range =
      "whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& s) -> std::string {
        long long v = 0;
        const char* end = s.data() + s.size();
        const auto [p, ec] = std::from_chars(s.data(), end, v);
        if (ec != std::errc() || p != end || v < lo || v > hi)
          return "must be a " + range + ", got '" + s + "'";
        return {};
      },
      range);
}

void require(bool ok, const std::string& option, const std::string& message) {
  if (!ok) throw CLI::ValidationError(option, message);
}

}  // namespace fieldlidar::app
