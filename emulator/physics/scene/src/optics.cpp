// D6 optics; the formula and its calibration are explained in optics.hpp and docs/scenes.md.
#include "ldoem/scene/optics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ldoem::scene {
namespace {

// The fraction of the hemisphere a receiver of diameter d sees at distance l is d^2 / (8 l^2).
double lambert_geometry(const OpticsConfig& optics) {
  const double d = optics.receiver_diameter_m;
  return optics.emitted_intensity / std::numbers::pi * d * d / 8.0;
}

bool all_finite(double a, double b, double c) {
  return std::isfinite(a) && std::isfinite(b) && std::isfinite(c);
}

}  // namespace

double calibration_for_max_range(const OpticsConfig& optics, double max_range_m) {
  return optics.min_irradiance * max_range_m * max_range_m / lambert_geometry(optics);
}

double max_range_at_full_reflectance(const OpticsConfig& optics) {
  return std::sqrt(optics.calibration * lambert_geometry(optics) / optics.min_irradiance);
}

double received_irradiance(const OpticsConfig& optics, double reflectance, double cos_incidence,
                           double range_m) {
  if (!all_finite(reflectance, cos_incidence, range_m)) return 0.0;
  const double r = std::clamp(reflectance, 0.0, kRetroReflectiveGain);
  const double cos_alpha = std::clamp(cos_incidence, 0.0, 1.0);
  const double l = std::max(range_m, kMinIrradianceRange_m);
  return optics.calibration * lambert_geometry(optics) * r * cos_alpha / (l * l);
}

double max_detectable_range(const OpticsConfig& optics, double reflectance, double cos_incidence) {
  if (!std::isfinite(reflectance) || !std::isfinite(cos_incidence)) return 0.0;
  const double r = std::clamp(reflectance, 0.0, 1.0);
  const double cos_alpha = std::clamp(cos_incidence, 0.0, 1.0);
  return max_range_at_full_reflectance(optics) * std::sqrt(r * cos_alpha);
}

std::uint16_t echo_value(const OpticsConfig& optics, double irradiance) {
  if (!std::isfinite(irradiance) || irradiance <= 0.0) return 0;
  if (optics.echo_scale == EchoScale::log) {
    const double decades = std::log10(irradiance / optics.min_irradiance);
    const double echo = std::round(kEchoAtThreshold + kLogEchoPerDecade * decades);
    return static_cast<std::uint16_t>(std::clamp(echo, 1.0, 65535.0));
  }
  const double echo = std::round(1000.0 * irradiance / optics.min_irradiance);
  return static_cast<std::uint16_t>(std::min(echo, 65535.0));
}

}  // namespace ldoem::scene
