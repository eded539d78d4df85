// Private helper: the motor models integrate in seconds and radians while their interfaces take
// SimTime and turns per second (Hz); the two conversions, named once for the model sources.
#pragma once

#include <ldoem/base/sim_time.hpp>

#include <chrono>
#include <numbers>

namespace ldoem::motor::detail {

inline constexpr double kRadiansPerTurn = 2.0 * std::numbers::pi;

inline double seconds(base::SimTime duration) { return std::chrono::duration<double>(duration).count(); }

}  // namespace ldoem::motor::detail
