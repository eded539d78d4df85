#include "ldoem/scan/scan_plan.hpp"

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <optional>

#include "ldoem/protocol/messages.hpp"

namespace ldoem::scan {
namespace {

using base::Unexpected;

// Tolerance for "is an integer": the options are decimal texts such as 0.18 / 0.09.
constexpr double kIntegerTolerance = 1e-6;

std::optional<long long> as_integer(double value) {
  const double rounded = std::round(value);
  if (!std::isfinite(value) || std::fabs(value - rounded) > kIntegerTolerance * std::max(1.0, std::fabs(value))) {
    return std::nullopt;
  }
  return static_cast<long long>(rounded);
}

Unexpected<std::string> plan_error(std::string text) { return Unexpected<std::string>(std::move(text)); }

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

}  // namespace

Expected<SectorPlan, std::string> plan_sectors(double horizontal_apex_deg, double horizontal_resolution_deg,
                                               std::uint16_t motor_speed_hz) {
  if (motor_speed_hz < kMinMotorSpeedHz || motor_speed_hz > kMaxMotorSpeedHz) {
    return plan_error("speed " + std::to_string(motor_speed_hz) + " Hz is outside 5..20 Hz (spec 6)");
  }
  const auto step_ticks = as_integer(horizontal_resolution_deg * kTicksPerDegree);
  if (!step_ticks || *step_ticks <= 0 || *step_ticks % kAngleStepGranuleTicks != 0 ||
      kTicksPerTurn % *step_ticks != 0) {
    return plan_error("horizontal resolution " + number(horizontal_resolution_deg) +
                      " deg is not a multiple of 0.125 deg dividing 360 deg (spec 6)");
  }
  SectorPlan plan;
  plan.angle_step_ticks = static_cast<std::uint16_t>(*step_ticks);
  plan.max_pulse_frequency_hz = static_cast<double>(kTicksPerTurn / *step_ticks) * motor_speed_hz;
  if (plan.max_pulse_frequency_hz > kMaxPulseFrequencyHz) {
    return plan_error("maximum pulse frequency " + number(plan.max_pulse_frequency_hz) +
                      " Hz is above 14400 Hz: use a coarser resolution or a lower speed (spec 5)");
  }
  const auto half_apex_ticks = as_integer(horizontal_apex_deg * kTicksPerDegree / 2.0);
  if (!half_apex_ticks || *half_apex_ticks <= 0 || *half_apex_ticks % *step_ticks != 0) {
    return plan_error("half the horizontal apex (" + number(horizontal_apex_deg / 2.0) +
                      " deg) must be a positive multiple of the resolution (spec 3.6: stops on the step grid)");
  }
  // Sector 1 (no measurement) ends one step before sector 0 starts at -half_apex.
  const long long blank_stop = static_cast<long long>(kTicksPerTurn) - *half_apex_ticks - *step_ticks;
  if (blank_stop <= *half_apex_ticks) {
    return plan_error("horizontal apex " + number(horizontal_apex_deg) + " deg leaves no room for a blanked sector");
  }
  // Spec 5: a measuring sector's area is its stop minus the previous sector's stop (mod 360).
  const double area_ticks = static_cast<double>(*half_apex_ticks + (kTicksPerTurn - blank_stop));
  plan.mean_pulse_frequency_hz = plan.max_pulse_frequency_hz * area_ticks / kTicksPerTurn;
  if (plan.mean_pulse_frequency_hz > kMaxMeanPulseFrequencyHz) {
    return plan_error("mean pulse frequency " + number(plan.mean_pulse_frequency_hz) +
                      " Hz is above 10800 Hz: narrow the apex or lower the speed (spec 5)");
  }
  plan.half_apex_ticks = static_cast<std::uint16_t>(*half_apex_ticks);
  plan.sectors = {{protocol::sector_function::kNormalMeasurement, static_cast<std::uint16_t>(*half_apex_ticks)},
                  {protocol::sector_function::kNoMeasurement, static_cast<std::uint16_t>(blank_stop)}};
  plan.beams_per_profile = static_cast<std::uint32_t>(2 * *half_apex_ticks / *step_ticks + 1);
  return plan;
}

Expected<LayerPlan, std::string> plan_layers(double vertical_apex_deg, double vertical_resolution_deg, bool half_step) {
  if (!std::isfinite(vertical_resolution_deg) || vertical_resolution_deg <= 0.0) {
    return plan_error("vertical resolution must be > 0 deg");
  }
  if (!std::isfinite(vertical_apex_deg) || vertical_apex_deg < 0.0 || vertical_apex_deg >= 180.0) {
    return plan_error("vertical apex must be in [0, 180) deg");
  }
  LayerPlan plan;
  plan.mode = half_step ? StepMode::half_step : StepMode::full_step;
  const double step_deg = protocol::output_shaft_deg_per_step(plan.mode);
  const auto steps = as_integer(vertical_resolution_deg / step_deg);
  if (!steps || *steps <= 0) {
    return plan_error("vertical resolution " + number(vertical_resolution_deg) + " deg is not a whole number of " +
                      number(step_deg) + " deg steps (D8" + (half_step ? ", half step)" : ", full step)"));
  }
  plan.steps_per_layer = static_cast<std::uint32_t>(*steps);
  plan.layer_count = static_cast<std::uint32_t>(std::llround(vertical_apex_deg / vertical_resolution_deg)) + 1;
  const std::int64_t total_steps = static_cast<std::int64_t>(plan.layer_count - 1) * plan.steps_per_layer;
  plan.start_steps = -(total_steps / 2);
  return plan;
}

}  // namespace ldoem::scan
