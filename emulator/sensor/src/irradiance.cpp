#include <ldoem/sensor/irradiance.hpp>

#include <cmath>
#include <numbers>

namespace ldoem::sensor {
namespace {

// (I0 / pi) d^2 / 8: the radiance of a white Lambertian target times the receiver's share of the
// hemisphere at 1 m, before calibration (D6).
double geometric_factor(const scene::OpticsConfig& optics) {
  const double diameter_m = optics.receiver_diameter_m;
  return optics.emitted_intensity / std::numbers::pi * diameter_m * diameter_m / 8.0;
}

}  // namespace

double received_irradiance(const scene::OpticsConfig& optics, double reflectance, double cos_incidence,
                           double range_m) {
  if (!std::isfinite(range_m) || range_m <= 0.0) return 0.0;
  if (!(reflectance > 0.0) || !(cos_incidence > 0.0)) return 0.0;  // also rejects NaN
  const double irradiance =
      optics.calibration * reflectance * cos_incidence * geometric_factor(optics) / (range_m * range_m);
  return std::isfinite(irradiance) ? irradiance : 0.0;
}

double calibration_for_max_range(const scene::OpticsConfig& optics) {
  const double l_max = optics.max_range_at_full_reflectance_m;
  return optics.min_irradiance * l_max * l_max / geometric_factor(optics);
}

double max_detectable_range_m(const scene::OpticsConfig& optics, double reflectance, double cos_incidence) {
  if (!(reflectance > 0.0) || !(cos_incidence > 0.0) || !(optics.min_irradiance > 0.0)) return 0.0;
  return std::sqrt(optics.calibration * reflectance * cos_incidence * geometric_factor(optics) /
                   optics.min_irradiance);
}

}  // namespace ldoem::sensor
