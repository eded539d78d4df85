// D6 received irradiance of a Lambertian target. Helper B1's scene/optics.hpp was not present
// when this was written; this is the same formula and should be folded into it when it lands.
#pragma once

#include <ldoem/scene/scene.hpp>

namespace ldoem::sensor {

// I_rs = calibration * (r I0 / pi) cos(alpha) d^2 / (8 l^2)  (D6).
// Guarded: a non-finite or non-positive range, or a negative cos/reflectance, gives 0 (no power),
// never NaN or infinity.
[[nodiscard]] double received_irradiance(const scene::OpticsConfig& optics, double reflectance,
                                         double cos_incidence, double range_m);

// The calibration that makes l_max(r = 1, alpha = 0) equal max_range_at_full_reflectance_m (D6:
// 63.1 m with the paper's constants). The scene loader sets OpticsConfig::calibration with this.
[[nodiscard]] double calibration_for_max_range(const scene::OpticsConfig& optics);

// Range at which a target of reflectance r at incidence cos alpha drops below I_rs_min.
[[nodiscard]] double max_detectable_range_m(const scene::OpticsConfig& optics, double reflectance,
                                            double cos_incidence);

}  // namespace ldoem::sensor
