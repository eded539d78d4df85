// D14 (docs/decisions-local.md): what SET_FILTER's near-field suppression (FILTERITEM 0x0001)
// does to a profile. With the filter on, every point measured nearer than kNearFieldLimit_q8
// (2 m) is reported as "no echo" (DISTANCE 0, ECHO 0, D3): the returns of dust, rain, insects or
// a dirty window close to the scanner are dropped, at the price of real targets that near. With
// the filter off (the factory setting) nothing changes. Applied where the control unit forms a
// profile, after the sensor model, so every transport and every stream sees the same points.
#pragma once

#include "ldoem/control/ports.hpp"

#include <cstdint>
#include <span>

namespace ldoem::control {

inline constexpr std::uint16_t kNearFieldLimit_q8 = 2 * 256;  // 2.0 m in 1/256 m

// Replaces every return nearer than kNearFieldLimit_q8 by "no echo"; returns how many it replaced.
inline std::size_t suppress_near_field(std::span<BeamReturn> returns) {
  std::size_t suppressed = 0;
  for (BeamReturn& beam : returns) {
    if (beam.distance_q8_m != 0 && beam.distance_q8_m < kNearFieldLimit_q8) {
      beam = BeamReturn{};
      ++suppressed;
    }
  }
  return suppressed;
}

}  // namespace ldoem::control
