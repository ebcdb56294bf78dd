#pragma once
// Random numbers for the simulated sensor noise (range noise, random dropout).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace fieldlidar::sim::detail {

/// splitmix64: small, fast, good enough for sensor noise; seeded per sweep.
struct NoiseRng {
  std::uint64_t state;
  bool has_spare = false;
  double spare = 0.0;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  /// Standard normal (Box-Muller; the second value of each pair is kept for the next call).
  double normal() {
    if (has_spare) {
      has_spare = false;
      return spare;
    }
    constexpr double kTwoPi = 2 * std::numbers::pi;
    const double u1 = std::max(uniform(), 1e-300), u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare = r * std::sin(kTwoPi * u2);
    has_spare = true;
    return r * std::cos(kTwoPi * u2);
  }
};

}  // namespace fieldlidar::sim::detail
