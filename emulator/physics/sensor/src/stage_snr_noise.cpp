// D13 snr_noise: the receiver's own noise, of standard deviation n = I_rs_min / threshold_snr,
// rides on the echo's height. Detection is decided on the noisy height P + n G1 against the
// threshold (so near the threshold a return comes and goes with the draw), the noisy height is
// the beam's I_rs from here on (ECHO), and the range gets the timing jitter of an edge of that
// signal-to-noise ratio, sigma_pulse / SNR (sigma_pulse the pulse's width in range, waveform's
// pulse_width_s), on top of the scene's constant sigma: sigma^2 = sigma_m^2 + (sigma_pulse / SNR)^2.
// Both draws come from the beam's counter-based stream (seed, revolution, beam, sub-stream 0),
// which replaces `noise` (the loader refuses both at once).
#include "hit_geometry.hpp"
#include "pulse_range.hpp"
#include "received_power.hpp"

#include <ldoem/sensor/effects.hpp>
#include <ldoem/sensor/noise_stream.hpp>

#include <cmath>
#include <sstream>

namespace ldoem::sensor {
namespace {

class SnrNoiseStage final : public BeamStage {
 public:
  SnrNoiseStage(const scene::ScannerConfig& scanner, const detail::ReceivedPower& power, bool waveform_thresholds)
      : noise_(scanner.noise),
        power_(power),
        noise_rms_(scanner.optics.min_irradiance / scanner.snr_noise.threshold_snr),
        threshold_(scanner.optics.min_irradiance * (waveform_thresholds ? scanner.waveform.threshold_factor : 1.0)),
        pulse_sigma_m_(detail::pulse_sigma_m(scanner.waveform.pulse_width_s)) {}

  std::string_view name() const override { return "snr_noise"; }

  std::string describe() const override {
    std::ostringstream text;
    text << "snr_noise: noise rms " << noise_rms_ << ", threshold " << threshold_ << ", pulse sigma "
         << pulse_sigma_m_ << " m, floor sigma " << noise_.sigma_m << " m, mean " << noise_.mean_m << " m";
    return text.str();
  }

  void apply(BeamState& beam, const BeamContext& context, BeamCounters& counters) const override {
    if (!beam.has_return) return;
    const double signal = beam.irradiance ? *beam.irradiance
                                          : power_(beam.reflectance, beam.cos_incidence, beam.range_m);
    NoiseStream stream(NoiseKey{.seed = context.seed, .revolution = context.revolution,
                                .beam_index = context.beam_index, .sub_stream = 0});
    const double noisy_signal = signal + noise_rms_ * stream.standard_normal();
    const double range_normal = stream.standard_normal();
    counters.random_draws += stream.draws();
    if (!(noisy_signal >= threshold_)) {
      beam.has_return = false;
      return;
    }
    beam.irradiance = noisy_signal;
    const double snr = signal / noise_rms_;
    const double jitter_m = pulse_sigma_m_ / snr;
    const double sigma_m = std::sqrt(noise_.sigma_m * noise_.sigma_m + jitter_m * jitter_m);
    beam.range_m += sigma_m * range_normal + noise_.mean_m;
  }

 private:
  scene::NoiseConfig noise_;
  detail::ReceivedPower power_;
  double noise_rms_;
  double threshold_;
  double pulse_sigma_m_;
};

}  // namespace

std::unique_ptr<BeamStage> make_snr_noise_stage(const scene::ScannerConfig& scanner, bool use_incidence,
                                                const std::optional<scene::AtmosphereConfig>& atmosphere,
                                                bool waveform_thresholds) {
  return std::make_unique<SnrNoiseStage>(scanner, detail::ReceivedPower(scanner.optics, use_incidence, atmosphere),
                                         waveform_thresholds);
}

}  // namespace ldoem::sensor
