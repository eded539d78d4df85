#include <ldoem/sensor/beam_sample.hpp>

#include <cmath>
#include <limits>

namespace ldoem::sensor {
namespace {
constexpr double kMaxEncodable = std::numeric_limits<std::uint16_t>::max();
}

std::optional<std::uint16_t> quantise_range(double range_m, const RangeLimits& limits) {
  if (!std::isfinite(range_m)) return std::nullopt;
  if (range_m < limits.min_range_m || range_m > limits.max_range_m) return std::nullopt;
  const double units = std::round(range_m * kDistanceUnitsPerMetre);
  if (units < 1.0 || units > kMaxEncodable) return std::nullopt;  // 0 is reserved for "no echo"
  return static_cast<std::uint16_t>(units);
}


}  // namespace ldoem::sensor
