// The laser pulse in range units, as the stages that time echoes (waveform, snr_noise) see it:
// a time is half the distance light covers in it, out and back.
#pragma once

#include <cmath>
#include <numbers>

namespace ldoem::sensor::detail {

inline constexpr double kSpeedOfLight_m_s = 299'792'458.0;

// The range a time span covers: c t / 2.
inline double range_of_time_m(double time_s) { return 0.5 * kSpeedOfLight_m_s * time_s; }

// The sigma, in range, of a Gaussian pulse `pulse_width_s` wide at half maximum
// (FWHM = 2 sqrt(2 ln 2) sigma).
inline double pulse_sigma_m(double pulse_width_s) {
  return range_of_time_m(pulse_width_s) / (2.0 * std::sqrt(2.0 * std::numbers::ln2));
}

}  // namespace ldoem::sensor::detail
