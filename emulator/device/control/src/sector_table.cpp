#include "ldoem/control/sector_table.hpp"

#include <cassert>

namespace ldoem::control {
namespace {

constexpr std::uint16_t kNotInitialised = static_cast<std::uint16_t>(SectorFunction::not_initialised);

// (stop_i - stop_{i-1}) mod 5760 for each initialised sector, sector 0 measured from the last
// initialised one (the table wraps, spec 3.6). Stops must be <= 5760 (checked by the caller).
std::vector<std::uint32_t> spans_of(const SectorTable& table, std::size_t count) {
  std::vector<std::uint32_t> spans;
  if (count == 1) {
    spans.push_back(kTicksPerTurn);  // a lone sector covers the whole turn
    return spans;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t stop = table[i].stop_ticks % kTicksPerTurn;
    const std::uint32_t previous = table[(i + count - 1) % count].stop_ticks % kTicksPerTurn;
    spans.push_back((stop + kTicksPerTurn - previous) % kTicksPerTurn);
  }
  return spans;
}

bool borders_configured(const SectorTable& table, std::size_t count) {
  if (count == 0) return false;
  bool any_measuring = false;
  for (std::size_t i = 0; i < count; ++i) {
    if (table[i].stop_ticks > kTicksPerTurn) return false;
    any_measuring = any_measuring || is_measuring(table[i].function);
  }
  if (!any_measuring) return false;
  std::uint32_t total = 0;
  for (const std::uint32_t span : spans_of(table, count)) {
    if (span == 0) return false;
    total += span;
  }
  return total == kTicksPerTurn;
}

}  // namespace

std::size_t initialised_sector_count(const SectorTable& table) {
  std::size_t count = 0;
  while (count < table.size() && table[count].function != kNotInitialised) ++count;
  return count;
}

MeasureCheck check_measure_configuration(const SectorTable& table, std::uint16_t angle_step_ticks,
                                         std::uint16_t motor_speed_hz) {
  assert(angle_step_ticks != 0 && kTicksPerTurn % angle_step_ticks == 0);
  const std::uint32_t max_pulse_hz = (kTicksPerTurn / angle_step_ticks) * motor_speed_hz;
  if (max_pulse_hz > kMaxPulseFrequencyHz) return MeasureCheck::max_pulse_frequency_too_high;

  const std::size_t count = initialised_sector_count(table);
  if (!borders_configured(table, count)) return MeasureCheck::sector_borders_not_configured;
  for (std::size_t i = 0; i < count; ++i) {
    if (table[i].stop_ticks % angle_step_ticks != 0) {
      return MeasureCheck::sector_borders_not_multiple_of_step;
    }
  }
  // mean = max * measuring / 5760 = f * measuring / step; compared without division.
  const std::vector<std::uint32_t> spans = spans_of(table, count);
  std::uint32_t measuring_ticks = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (is_measuring(table[i].function)) measuring_ticks += spans[i];
  }
  if (std::uint64_t{motor_speed_hz} * measuring_ticks >
      std::uint64_t{kMaxMeanPulseFrequencyHz} * angle_step_ticks) {
    return MeasureCheck::mean_pulse_frequency_too_high;
  }
  return MeasureCheck::ok;
}

std::vector<SectorGeometry> sector_geometry(const SectorTable& table, std::uint16_t angle_step_ticks) {
  const std::size_t count = initialised_sector_count(table);
  std::vector<SectorGeometry> geometry;
  if (count == 0) return geometry;
  const std::vector<std::uint32_t> spans = spans_of(table, count);
  // Sector 0 starts one step after the stop of the last initialised sector (spec 3.6).
  std::uint32_t start = (table[count - 1].stop_ticks + angle_step_ticks) % kTicksPerTurn;
  for (std::size_t i = 0; i < count; ++i) {
    SectorGeometry sector;
    sector.sector = static_cast<std::uint16_t>(i);
    sector.function = table[i].function;
    sector.span_ticks = spans[i];
    sector.first_angle_unwrapped_ticks = start;
    sector.last_angle_unwrapped_ticks = start + spans[i] - angle_step_ticks;
    sector.point_count = is_measuring(table[i].function) ? spans[i] / angle_step_ticks : 0;
    geometry.push_back(sector);
    start += spans[i];
  }
  return geometry;
}

std::string describe(MeasureCheck check) {
  switch (check) {
    case MeasureCheck::ok: return "ok";
    case MeasureCheck::max_pulse_frequency_too_high: return "maximum pulse frequency too high";
    case MeasureCheck::mean_pulse_frequency_too_high: return "mean pulse frequency too high";
    case MeasureCheck::sector_borders_not_configured: return "sector borders not configured correctly";
    case MeasureCheck::sector_borders_not_multiple_of_step:
      return "sector borders not a multiple of the angle step";
  }
  return "unknown measure check";
}

}  // namespace ldoem::control
