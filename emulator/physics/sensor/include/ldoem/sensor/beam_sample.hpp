// The last step of every beam: what the encoder gets. Distances in 1/256 m, 0 = no echo (D3);
// NaN and infinity never get past quantise_range().
#pragma once

#include <cstdint>
#include <optional>

namespace ldoem::sensor {

struct BeamSample {
  std::uint16_t distance = 0;  // 1/256 m; 0 = no echo (D3)
  std::uint16_t echo = 0;      // ECHO-n (D6); 0 when distance is 0
  friend bool operator==(const BeamSample&, const BeamSample&) = default;
};

inline constexpr double kDistanceUnitsPerMetre = 256.0;  // D6: ranges quantised to 1/256 m

// ECHO when the scene does not name `intensity`: no irradiance is computed, so every echo reports
// the level of a return exactly at the detection threshold (1000 * I_rs_min / I_rs_min).
inline constexpr std::uint16_t kEchoWithoutIntensity = 1000;

struct RangeLimits {
  double min_range_m = 0.9;   // D_min (D6)
  double max_range_m = 30.0;  // D_max (D6), <= 255.99 m
};

// D6: require D_min <= range <= D_max on the measured range (after noise), then round to
// 1/256 m (so a target exactly at D_min = 0.9 m is measured, as 230/256 m). Non-finite,
// out-of-limit or unencodable ranges give nothing, which the encoder writes as DISTANCE 0 (D3).
[[nodiscard]] std::optional<std::uint16_t> quantise_range(double range_m, const RangeLimits& limits);

}  // namespace ldoem::sensor
