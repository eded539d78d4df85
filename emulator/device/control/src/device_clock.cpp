#include "ldoem/control/device_clock.hpp"

namespace ldoem::control {

std::int64_t floor_ms(base::SimTime now) {
  constexpr std::int64_t kNsPerMs = 1'000'000;
  const std::int64_t ns = now.count();
  std::int64_t ms = ns / kNsPerMs;
  if (ns % kNsPerMs < 0) --ms;
  return ms;
}

DeviceClock DeviceClock::reading(base::SimTime now, std::uint16_t value_ms) {
  DeviceClock clock;
  clock.set(now, value_ms);
  return clock;
}

std::uint16_t DeviceClock::value_at(base::SimTime now) const {
  // Unsigned 16-bit arithmetic is the wrap modulo 65536.
  return static_cast<std::uint16_t>(offset_ms_ + static_cast<std::uint64_t>(floor_ms(now)));
}

void DeviceClock::set(base::SimTime now, std::uint16_t value_ms) {
  offset_ms_ = static_cast<std::uint16_t>(value_ms - static_cast<std::uint64_t>(floor_ms(now)));
}

void DeviceClock::add(std::int16_t delta_ms) {
  offset_ms_ = static_cast<std::uint16_t>(offset_ms_ + static_cast<std::uint16_t>(delta_ms));
}

}  // namespace ldoem::control
