#include "ldoem/control/revolution_timing.hpp"

#include <cassert>

#include "ldoem/control/sector_table.hpp"

namespace ldoem::control {
namespace {
constexpr std::int64_t kNsPerSecond = 1'000'000'000;
}

base::SimTime revolution_time(base::SimTime epoch, std::uint16_t speed_hz, std::uint64_t revolution,
                                  std::uint32_t angle_unwrapped_ticks) {
  assert(speed_hz > 0);
  // Whole seconds first so that the products stay far from 64-bit overflow for any uptime.
  const std::uint64_t whole_seconds = revolution / speed_hz;
  const std::uint64_t turns_in_second = revolution % speed_hz;
  const std::uint64_t ticks = turns_in_second * kTicksPerTurn + angle_unwrapped_ticks;
  const std::uint64_t ns = ticks * kNsPerSecond / (std::uint64_t{kTicksPerTurn} * speed_hz);
  return epoch + base::SimTime(static_cast<std::int64_t>(whole_seconds) * kNsPerSecond +
                                   static_cast<std::int64_t>(ns));
}

std::uint64_t first_revolution_starting_at_or_after(base::SimTime epoch, std::uint16_t speed_hz,
                                                    base::SimTime t) {
  assert(speed_hz > 0);
  if (t <= epoch) return 0;
  const std::int64_t elapsed_ns = (t - epoch).count();
  // Estimate, then correct for the floor in revolution_time.
  std::uint64_t revolution = static_cast<std::uint64_t>(elapsed_ns / kNsPerSecond) * speed_hz +
                             static_cast<std::uint64_t>((elapsed_ns % kNsPerSecond) * speed_hz / kNsPerSecond);
  while (revolution_time(epoch, speed_hz, revolution, 0) < t) ++revolution;
  while (revolution > 0 && revolution_time(epoch, speed_hz, revolution - 1, 0) >= t) --revolution;
  return revolution;
}

}  // namespace ldoem::control
