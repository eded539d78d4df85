// Private helpers shared by the casting stages.
#pragma once

#include <ldoem/raycast/ray_caster.hpp>

#include <algorithm>
#include <cmath>

namespace ldoem::sensor::detail {

// cos(alpha) of D6: the normal faces against the ray, so cos alpha = -d . n, clamped to [0, 1]
// (a grazing ray gives 0 and therefore no power, never a negative or NaN factor).
inline double cos_incidence(const Eigen::Vector3d& direction, const Eigen::Vector3d& normal) {
  const double cosine = -direction.dot(normal);
  return std::isfinite(cosine) ? std::clamp(cosine, 0.0, 1.0) : 0.0;
}

// A caster may break its contract; a hit whose range is not a finite positive number is a miss.
inline bool usable_hit(const raycast::Hit& hit) { return std::isfinite(hit.range_m) && hit.range_m > 0.0; }

}  // namespace ldoem::sensor::detail
