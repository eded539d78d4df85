// D6 optics: the paper's Lambertian return, computed in SI with one calibration constant.
//
//   I_rs = calibration * (r I0 / pi) * cos(alpha) * d^2 / (8 l^2)
//
// With calibration = 8 pi I_rs_min L^2 / (I0 d^2) the return at r = 1, alpha = 0 falls to the
// dropout threshold I_rs_min exactly at l = L (max_range_at_full_reflectance_m, 63.1 m by
// default, the range the paper's constants give with d in cm and l in m), and in general
// l_max(r, alpha) = L sqrt(r cos alpha). The loader sets OpticsConfig::calibration this way
// unless the scene gives a calibration itself (docs/scenes.md).
#pragma once

#include "ldoem/scene/scene.hpp"

#include <cstdint>

namespace ldoem::scene {

// The calibration that makes l_max(r = 1, alpha = 0) equal max_range_m. Needs positive inputs.
double calibration_for_max_range(const OpticsConfig& optics, double max_range_m);

// The inverse: the range at which a white target seen head-on drops out, for optics.calibration.
double max_range_at_full_reflectance(const OpticsConfig& optics);

// I_rs for a Lambertian target. Guards (never NaN or Inf): reflectance is clamped to
// [0, kRetroReflectiveGain] (a retro-reflector's optical reflectance exceeds 1), cos_incidence to
// [0, 1], ranges below kMinIrradianceRange_m count as that range, and any
// non-finite argument gives 0 (no light).
inline constexpr double kMinIrradianceRange_m = 1e-6;
double received_irradiance(const OpticsConfig& optics, double reflectance, double cos_incidence,
                           double range_m);

// l_max(r, alpha) = L sqrt(r cos alpha), with the same clamping; 0 for non-finite arguments.
double max_detectable_range(const OpticsConfig& optics, double reflectance, double cos_incidence);

// ECHO-n; 0 for non-finite or non-positive input. EchoScale::linear (D6, the default):
// min(65535, round(1000 * I_rs / I_rs_min)), which saturates at 65.5 times the threshold.
// EchoScale::log: clamp(round(1000 + 8000 log10(I_rs / I_rs_min)), 1, 65535): strictly
// increasing in I_rs up to 10^8.07 times the threshold, 1000 at the threshold as in D6.
inline constexpr double kEchoAtThreshold = 1000.0;
inline constexpr double kLogEchoPerDecade = 8000.0;
std::uint16_t echo_value(const OpticsConfig& optics, double irradiance);

}  // namespace ldoem::scene
