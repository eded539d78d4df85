// I_rs of one hit as every stage computes it: D6's Lambert formula (scene/optics.hpp; a
// retro-reflective object arrives with its gain already in the hit's reflectance), cos(alpha)
// only with `incidence`, and with `atmosphere` the two-way Beer-Lambert transmission
// exp(-2 k l), k = 3.912 / V (Koschmieder: V is where contrast falls to 2 %). Without
// `atmosphere` nothing is multiplied, so the result is D6's to the last bit.
#pragma once

#include <ldoem/scene/optics.hpp>
#include <ldoem/scene/scene.hpp>

#include <cmath>
#include <optional>

namespace ldoem::sensor::detail {

// Koschmieder's constant: ln(1 / 0.02), the 2 % contrast threshold that defines visibility.
inline constexpr double kKoschmiederConstant = 3.912;

class ReceivedPower {
 public:
  ReceivedPower(const scene::OpticsConfig& optics, bool use_incidence,
                const std::optional<scene::AtmosphereConfig>& atmosphere)
      : optics_(optics),
        use_incidence_(use_incidence),
        extinction_per_m_(atmosphere ? kKoschmiederConstant / atmosphere->visibility_m : 0.0) {}

  [[nodiscard]] double operator()(double reflectance, double cos_incidence, double range_m) const {
    const double irradiance =
        scene::received_irradiance(optics_, reflectance, use_incidence_ ? cos_incidence : 1.0, range_m);
    if (extinction_per_m_ == 0.0) return irradiance;
    return irradiance * two_way_transmission(range_m);
  }

  [[nodiscard]] double two_way_transmission(double range_m) const {
    return std::isfinite(range_m) ? std::exp(-2.0 * extinction_per_m_ * std::max(range_m, 0.0)) : 0.0;
  }

  [[nodiscard]] const scene::OpticsConfig& optics() const { return optics_; }
  [[nodiscard]] bool use_incidence() const { return use_incidence_; }
  [[nodiscard]] double extinction_per_m() const { return extinction_per_m_; }

 private:
  scene::OpticsConfig optics_;
  bool use_incidence_;
  double extinction_per_m_;
};

}  // namespace ldoem::sensor::detail
