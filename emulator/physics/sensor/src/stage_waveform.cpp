// D13 waveform: every sub-ray of the beam's footprint (mixed_pixels' pattern) returns a Gaussian
// pulse at its own range, with its share of the beam's power (its I_rs over the sub-ray count)
// as amplitude; the sum is the received waveform. The receiver is a peak detector: every hump
// (local maximum) of the waveform whose height reaches the detection threshold
// (threshold_factor * I_rs_min) is an echo, timed at its peak. A clean pulse is therefore
// measured at its centre whatever its height; what is not a clean pulse walks: surfaces closer
// than about a pulse width merge into one hump whose peak lies between them, nearer the stronger,
// and a slanted surface spreads its sub-rays in range, stretching the pulse (lower, wider hump)
// and moving its peak with the power's distribution. Neither is a parameter. The echo reported
// is the first, the strongest or the last (WaveformConfig::detection); its peak height is the
// beam's I_rs from here on (ECHO, snr_noise).
//
// Everything is computed in range units (the pulse's time width times c / 2), on the analytic sum
// of Gaussians: a grid of half a pulse sigma finds the humps, golden sections refine them. Work
// is bounded: at most 37 pulses, each looked at only where it can help reach the threshold, and
// at most 4096 grid points per stretch.
#include "footprint.hpp"
#include "hit_geometry.hpp"
#include "pulse_range.hpp"
#include "received_power.hpp"

#include <ldoem/sensor/effects.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>

namespace ldoem::sensor {
namespace {

constexpr double kGridStepSigmas = 0.5;
constexpr double kMaxGridPoints = 4096.0;  // a stretch longer than 2048 sigma gets a coarser grid
constexpr int kGoldenSections = 60;       // shrinks the bracket by 0.618^60: far below a micrometre
// Fog's extinction-to-backscatter (lidar) ratio: droplets far larger than the wavelength scatter
// about 1/18.8 of what they extinguish back per steradian; ceilometers are calibrated on liquid
// water clouds with this value (docs/sensor-model.md).
constexpr double kFogLidarRatio_sr = 18.8;

struct Pulse {
  double range_m;
  double amplitude;      // I_rs share of this sub-ray
  double cos_incidence;
  double reflectance;
};

struct Echo {
  double range_m;   // where the receiver times the echo: its peak
  double peak;      // the waveform's height there
  double peak_at_m;
};

class Waveform {
 public:
  Waveform(std::span<const Pulse> pulses, double sigma_m) : pulses_(pulses), sigma_m_(sigma_m) {}
  [[nodiscard]] double at(double range_m) const {
    double sum = 0.0;
    for (const Pulse& pulse : pulses_) {
      const double z = (range_m - pulse.range_m) / sigma_m_;
      sum += pulse.amplitude * std::exp(-0.5 * z * z);
    }
    return sum;
  }

 private:
  std::span<const Pulse> pulses_;
  double sigma_m_;
};

class WaveformStage final : public BeamStage {
 public:
  WaveformStage(const scene::ScannerConfig& scanner, const detail::ReceivedPower& power)
      : config_(scanner.waveform),
        offsets_(hexagonal_subray_offsets(scanner.beam_divergence_rad, scanner.mixed_pixel_subrays)),
        power_(power),
        sigma_m_(detail::pulse_sigma_m(scanner.waveform.pulse_width_s)),
        threshold_(scanner.waveform.threshold_factor * scanner.optics.min_irradiance),
        fog_(fog_pulse(scanner, power_)) {}

  std::string_view name() const override { return "waveform"; }

  std::string describe() const override {
    static constexpr const char* kModes[] = {"first", "strongest", "last"};
    std::ostringstream text;
    text << "waveform: " << offsets_.size() << " sub-rays, pulse FWHM " << config_.pulse_width_s
         << " s (sigma " << sigma_m_ << " m of range), threshold " << threshold_ << ", detection "
         << kModes[static_cast<int>(config_.detection)];
    if (fog_) text << ", fog return at " << fog_->range_m << " m (amplitude " << fog_->amplitude << ")";
    return text.str();
  }

  void apply(BeamState& beam, const BeamContext& context, BeamCounters& counters) const override {
    detail::FootprintCast cast;
    detail::cast_footprint(beam.ray, offsets_, context.caster, cast);
    counters.rays_cast += cast.count;
    std::array<Pulse, detail::kMaxSubrays + 1> pulses;  // + fog's own
    std::size_t pulse_count = 0;
    if (fog_) pulses[pulse_count++] = *fog_;
    for (std::size_t i = 0; i < cast.count; ++i) {
      const std::optional<raycast::Hit>& hit = cast.hits[i];
      if (!hit || !detail::usable_hit(*hit)) continue;
      const double cosine = detail::cos_incidence(cast.rays[i].direction, hit->normal);
      const double amplitude = power_(hit->reflectance, cosine, hit->range_m) / static_cast<double>(cast.count);
      if (!(amplitude > 0.0)) continue;
      pulses[pulse_count++] = Pulse{hit->range_m, amplitude, cosine, hit->reflectance};
    }
    std::sort(pulses.begin(), pulses.begin() + static_cast<std::ptrdiff_t>(pulse_count),
              [](const Pulse& a, const Pulse& b) { return a.range_m < b.range_m; });
    const std::span<const Pulse> received(pulses.data(), pulse_count);
    const std::optional<Echo> echo = detect(received);
    if (!echo) {
      beam.has_return = false;
      return;
    }
    beam.has_return = true;
    beam.range_m = echo->range_m;
    beam.irradiance = echo->peak;
    // The surface that contributes most at the echo's peak stands for the echo.
    double largest = -1.0;
    for (const Pulse& pulse : received) {
      const double z = (echo->peak_at_m - pulse.range_m) / sigma_m_;
      const double contribution = pulse.amplitude * std::exp(-0.5 * z * z);
      if (contribution > largest) {
        largest = contribution;
        beam.cos_incidence = pulse.cos_incidence;
        beam.reflectance = pulse.reflectance;
      }
    }
  }

 private:
  // The echo the detection mode asks for, or nothing when the waveform never reaches the threshold.
  [[nodiscard]] std::optional<Echo> detect(std::span<const Pulse> pulses) const {
    if (pulses.empty()) return std::nullopt;
    const Waveform waveform(pulses, sigma_m_);
    const double count = static_cast<double>(pulses.size());
    std::optional<Echo> chosen;
    // Where the waveform can reach the threshold: near a pulse whose own height is at least
    // threshold / count (otherwise the sum of all of them stays below it). Overlapping reaches
    // are scanned as one stretch.
    std::size_t next = 0;
    while (next < pulses.size()) {
      double start_m = 0.0;
      double end_m = 0.0;
      bool open = false;
      for (; next < pulses.size(); ++next) {
        const double ratio = count * pulses[next].amplitude / threshold_;
        if (!(ratio > 1.0)) continue;
        const double reach_m = sigma_m_ * (std::sqrt(2.0 * std::log(ratio)) + 1.0);
        if (!open) {
          start_m = pulses[next].range_m - reach_m;
          end_m = pulses[next].range_m + reach_m;
          open = true;
        } else if (pulses[next].range_m - reach_m <= end_m) {
          end_m = std::max(end_m, pulses[next].range_m + reach_m);
        } else {
          break;
        }
      }
      if (!open) break;
      scan_stretch(waveform, start_m, end_m, chosen);
      if (chosen && config_.detection == scene::EchoDetection::first) return chosen;
    }
    return chosen;
  }

  // Finds the echoes in [start, end] (the waveform is below the threshold at both ends): every
  // local maximum of a grid of half a pulse sigma, refined, whose height reaches the threshold.
  void scan_stretch(const Waveform& waveform, double start_m, double end_m, std::optional<Echo>& chosen) const {
    const double step_m = std::max(kGridStepSigmas * sigma_m_, (end_m - start_m) / kMaxGridPoints);
    const auto steps = static_cast<std::size_t>(std::ceil((end_m - start_m) / step_m));
    double before = waveform.at(start_m);
    double middle = waveform.at(start_m + step_m);
    for (std::size_t k = 2; k <= steps + 1; ++k) {
      const double after_m = start_m + static_cast<double>(k) * step_m;
      const double after = waveform.at(after_m);
      if (middle > before && middle >= after) {
        const Echo echo = refine_peak(waveform, after_m - 2.0 * step_m, after_m);
        if (echo.peak >= threshold_) {
          offer(echo, chosen);
          if (config_.detection == scene::EchoDetection::first) return;
        }
      }
      before = middle;
      middle = after;
    }
  }

  void offer(const Echo& echo, std::optional<Echo>& chosen) const {
    switch (config_.detection) {
      case scene::EchoDetection::first:
        if (!chosen) chosen = echo;
        break;
      case scene::EchoDetection::strongest:
        if (!chosen || echo.peak > chosen->peak) chosen = echo;
        break;
      case scene::EchoDetection::last:
        chosen = echo;
        break;
    }
  }

  // Golden-section search for the maximum inside [low, high] (one hump of the waveform).
  [[nodiscard]] Echo refine_peak(const Waveform& waveform, double low_m, double high_m) const {
    const double inverse_phi = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int i = 0; i < kGoldenSections; ++i) {
      const double left_m = high_m - inverse_phi * (high_m - low_m);
      const double right_m = low_m + inverse_phi * (high_m - low_m);
      if (waveform.at(left_m) < waveform.at(right_m)) {
        low_m = left_m;
      } else {
        high_m = right_m;
      }
    }
    const double peak_at_m = 0.5 * (low_m + high_m);
    return Echo{.range_m = peak_at_m, .peak = waveform.at(peak_at_m), .peak_at_m = peak_at_m};
  }

  // Fog fills the whole footprint, so its backscatter is one pulse at the full beam's power, as
  // from a diffuse target of reflectance pi * beta * dr: beta = k / lidar ratio is the volume
  // backscatter per metre and steradian, dr = c * FWHM / 2 the depth of fog one time sample sees,
  // and a Lambertian target sends rho / pi per steradian back. It sits where the receiver first
  // sees the whole beam (fog_overlap_m): nearer, the biaxial optics hide it; farther, 1/r^2 and
  // extinction make it weaker. Same for every beam, so it costs one more pulse and no draws.
  static std::optional<Pulse> fog_pulse(const scene::ScannerConfig& scanner, const detail::ReceivedPower& power) {
    if (!scanner.atmosphere.fog_returns || power.extinction_per_m() == 0.0) return std::nullopt;
    const double backscatter_per_m_sr = power.extinction_per_m() / kFogLidarRatio_sr;
    const double depth_m = detail::range_of_time_m(scanner.waveform.pulse_width_s);
    const double reflectance = std::numbers::pi * backscatter_per_m_sr * depth_m;
    const double range_m = scanner.atmosphere.fog_overlap_m;
    return Pulse{range_m, power(reflectance, 1.0, range_m), 1.0, reflectance};
  }

  scene::WaveformConfig config_;
  std::vector<Eigen::Vector2d> offsets_;
  detail::ReceivedPower power_;
  double sigma_m_;
  double threshold_;
  std::optional<Pulse> fog_;
};

}  // namespace

std::unique_ptr<BeamStage> make_waveform_stage(const scene::ScannerConfig& scanner, bool use_incidence,
                                               const std::optional<scene::AtmosphereConfig>& atmosphere) {
  return std::make_unique<WaveformStage>(scanner, detail::ReceivedPower(scanner.optics, use_incidence, atmosphere));
}

}  // namespace ldoem::sensor
