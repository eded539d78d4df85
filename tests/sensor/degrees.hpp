// The sensor tests state angles in degrees and the sensor takes radians.
#pragma once

#include <numbers>

namespace ldoem::sensor::testing {

inline constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace ldoem::sensor::testing
