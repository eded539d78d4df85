// The sector table (spec 3.6) and the checks TRANS_MEASURE makes on it (spec 3.3, spec 5).
// Pure functions over values: no state, no time.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ldoem/base/device_constants.hpp"

namespace ldoem::control {

using base::kMaxMeanPulseFrequencyHz;
using base::kMaxPulseFrequencyHz;
using base::kTicksPerTurn;

// Sector functions (spec 3.6).
enum class SectorFunction : std::uint16_t {
  not_initialised = 0,  // terminates the table
  no_measurement = 1,
  reserved = 2,  // never accepted (SET_FUNCTION answers FF FF)
  normal_measurement = 3,
  reference_measurement = 4,
};

struct Sector {
  std::uint16_t function = 0;    // raw SectorFunction value, as SET_FUNCTION sent it
  std::uint16_t stop_ticks = 0;  // 1/16 degree; any value when function is 0 (S2 sends 0xFFF0)
  bool operator==(const Sector&) const = default;
};

inline constexpr std::size_t kSectorSlots = 8;  // sector numbers 0..7 (spec 3.6)
using SectorTable = std::array<Sector, kSectorSlots>;

constexpr bool is_measuring(std::uint16_t function) {
  return function == static_cast<std::uint16_t>(SectorFunction::normal_measurement) ||
         function == static_cast<std::uint16_t>(SectorFunction::reference_measurement);
}

// Number of initialised sectors: the sectors before the first function-0 one (spec 3.6: the
// first not-initialised sector terminates the table; sectors after it are ignored).
std::size_t initialised_sector_count(const SectorTable& table);

// TRANS_MEASURE return codes (spec 3.3), as the reasons a configuration is refused.
enum class MeasureCheck : std::uint16_t {
  ok = 0,
  max_pulse_frequency_too_high = 1,
  mean_pulse_frequency_too_high = 2,
  sector_borders_not_configured = 3,
  sector_borders_not_multiple_of_step = 4,
};

// The lead's rule set for TRANS_MEASURE, checked in the order 1, 3, 4, 2 (2 needs a valid table):
//  1: (5760 / step) * f > 14400 Hz;
//  3: no initialised sector, no measuring sector, a stop > 5760, a span of 0, or spans that do
//     not add up to exactly one turn;
//  4: a stop that is not a multiple of the step;
//  2: mean = f * (sum of measuring spans) / step > 10800 Hz. The span of a sector is
//     (stop_i - stop_{i-1}) mod 5760 (one step more than stop - start, as the LD counts it, spec 5);
//     a single initialised sector spans the whole turn.
// Precondition: angle_step_ticks divides 5760 (the global configuration guarantees it).
MeasureCheck check_measure_configuration(const SectorTable& table, std::uint16_t angle_step_ticks,
                                         std::uint16_t motor_speed_hz);

// Where a sector's points lie within a profile. Angles are "unwrapped": counted from angle 0 at
// the start of the profile's revolution and allowed past 5760, because the turn a profile
// covers starts at sector 0's start angle and sectors follow one another around the circle
// (spec 3.6), so a sector that passes through 0 deg continues into the next revolution. This
// keeps every sector's points, TSTART and TEND in time order.
struct SectorGeometry {
  std::uint16_t sector = 0;
  std::uint16_t function = 0;
  std::uint32_t first_angle_unwrapped_ticks = 0;  // STARTDIR = this mod 5760
  std::uint32_t last_angle_unwrapped_ticks = 0;   // ENDDIR = this mod 5760 (= the stop)
  std::uint32_t point_count = 0;                  // 0 for a non-measuring sector (D3)
  std::uint32_t span_ticks = 0;
};

// One entry per initialised sector, in sector-number order. Precondition: the table passed
// check_measure_configuration with this step (codes 3 and 4 absent).
std::vector<SectorGeometry> sector_geometry(const SectorTable& table, std::uint16_t angle_step_ticks);

constexpr std::uint16_t wrap_angle(std::uint32_t angle_unwrapped_ticks) {
  return static_cast<std::uint16_t>(angle_unwrapped_ticks % kTicksPerTurn);
}

std::string describe(MeasureCheck check);

}  // namespace ldoem::control
