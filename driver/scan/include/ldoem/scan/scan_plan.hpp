// The pure planning of an acquisition: which sector table makes the scanner measure only the
// horizontal apex (spec 3.6 and the pulse rules of spec 5), and which tilt positions the
// layers sit at (D8 step sizes). Errors are one line for the user.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ldoem/base/device_constants.hpp"
#include "ldoem/driver/scanner.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/lpt.hpp"

namespace ldoem::scan {

using base::Expected;
using base::kMaxMeanPulseFrequencyHz;
using base::kMaxMotorSpeedHz;
using base::kMaxPulseFrequencyHz;
using base::kMinMotorSpeedHz;
using base::kTicksPerDegree;
using base::kTicksPerTurn;
using protocol::StepMode;

// Angle steps are multiples of 0.125 deg (2 ticks, S1's check).
inline constexpr std::uint16_t kAngleStepGranuleTicks = 2;

struct SectorPlan {
  std::uint16_t angle_step_ticks = 4;
  // Sector 0 measures from -apex/2 to +apex/2 around +x (D5: angle 0 is +x), wrapping through
  // 0; sector 1 blanks the rest; write_sector_table ends the table after them.
  std::vector<driver::SectorDefinition> sectors;
  std::uint16_t half_apex_ticks = 0;
  std::uint32_t beams_per_profile = 0;  // 2 * half_apex / step + 1
  double mean_pulse_frequency_hz = 0.0;
  double max_pulse_frequency_hz = 0.0;
};

Expected<SectorPlan, std::string> plan_sectors(double horizontal_apex_deg, double horizontal_resolution_deg,
                                               std::uint16_t motor_speed_hz);

struct LayerPlan {
  std::uint32_t layer_count = 1;       // round(apex / resolution) + 1
  std::uint32_t steps_per_layer = 0;   // resolution / step size of `mode` (an integer)
  StepMode mode = StepMode::full_step;
  std::int64_t start_steps = 0;        // the low apex, in steps of `mode` from level (<= 0)

  std::int64_t half_steps_per_step() const { return mode == StepMode::half_step ? 1 : 2; }
  // The commanded position of layer `layer`, in half-steps (D8).
  std::int64_t layer_half_steps(std::uint32_t layer) const {
    return (start_steps + static_cast<std::int64_t>(layer) * steps_per_layer) * half_steps_per_step();
  }
  double layer_tilt_deg(std::uint32_t layer) const {
    return static_cast<double>(layer_half_steps(layer)) * protocol::kOutputShaftHalfStepDeg;
  }
};

Expected<LayerPlan, std::string> plan_layers(double vertical_apex_deg, double vertical_resolution_deg, bool half_step);

}  // namespace ldoem::scan
