// Shared pieces of the fits (internal): the sample generator, input checks, index helpers.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "ldoem/cloud/fitting.hpp"

namespace ldoem::cloud::detail {

// SplitMix64: fully specified, so a seed gives the same samples with every standard library
// (std::uniform_int_distribution is implementation-defined).
class SampleGenerator {
 public:
  explicit SampleGenerator(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    state_ += 0x9E3779B97F4A7C15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, bound), by rejection so no index is favoured. Precondition: bound > 0.
  std::size_t below(std::size_t bound) {
    const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() -
                                std::numeric_limits<std::uint64_t>::max() % bound;
    std::uint64_t draw = next();
    while (draw >= limit) draw = next();
    return static_cast<std::size_t>(draw % bound);
  }

 private:
  std::uint64_t state_;
};

// Checks every fit makes first: enough points, all finite, not all on one line.
std::optional<FitError> check_points(std::span<const Eigen::Vector3d> points, std::size_t minimum);

// Robust score of a residual: squared, capped at the threshold (MSAC).
inline double msac_cost(double residual, double threshold) {
  const double squared = residual * residual;
  const double cap = threshold * threshold;
  return squared < cap ? squared : cap;
}

// Distinct random indices (count <= points, count small).
template <std::size_t Count>
std::array<std::size_t, Count> distinct_sample(SampleGenerator& generator, std::size_t size) {
  std::array<std::size_t, Count> picked{};
  for (std::size_t slot = 0; slot < Count; ++slot) {
    bool repeated = true;
    while (repeated) {
      picked[slot] = generator.below(size);
      repeated = false;
      for (std::size_t earlier = 0; earlier < slot; ++earlier) repeated |= picked[earlier] == picked[slot];
    }
  }
  return picked;
}

}  // namespace ldoem::cloud::detail
