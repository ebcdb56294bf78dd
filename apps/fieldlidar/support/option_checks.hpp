#pragma once
// Valid ranges of the numeric options, checked by CLI11 while the command line is parsed: before
// any command runs or touches its outputs. Every check's description is the range shown in
// --help, and a value outside it fails as "--option: must be ..., got VALUE" (main() prints it as
// "fieldlidar: error: ..." with exit status 1). Checks between two options (an order, a
// minimum below a maximum) go through require(), called first thing in the command's callback.

#include <string>

#include <CLI/CLI.hpp>

namespace fieldlidar::app {

/// A real number in [lo, hi] (either end may be +-infinity: "at least", "at most").
CLI::Validator real_in(double lo, double hi);
/// A real number > lo (and <= hi).
CLI::Validator real_above(double lo, double hi = 1e300);
/// Any finite real number (NaN and infinity refused): values without a natural range, such as a
/// pose or a score margin.
CLI::Validator real_finite();
/// A whole number in [lo, hi]; "-5" for an unsigned option is refused, not wrapped.
CLI::Validator whole_in(long long lo, long long hi);

/// Throws CLI::ValidationError("OPTION: message") when `ok` is false: the relation of two options
/// checked in the same words as a single option's range.
void require(bool ok, const std::string& option, const std::string& message);

}  // namespace fieldlidar::app
