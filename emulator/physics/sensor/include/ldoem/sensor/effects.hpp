// D9 effects as small stages behind one interface, composed by EffectPipeline::build from the
// scene's EffectSet. The order is fixed here, not by the YAML (see docs/sensor-model.md):
//
//   cast (single ray, mixed_pixels' sub-rays, or waveform's pulses) -> snr_noise
//     -> intensity (+incidence) -> noise -> encode
//
// With `atmosphere` every stage that computes I_rs multiplies it by the two-way transmission.
//
// Only named effects are built; a scene that names none gets [single_ray] and the encoder: one
// cast per beam, no irradiance, no random numbers. No stage reads a clock, a global or the scene:
// everything it needs arrives at construction (parameters) or in BeamContext (caster, keys).
#pragma once

#include <ldoem/raycast/ray_caster.hpp>
#include <ldoem/scene/scene.hpp>
#include <ldoem/sensor/beam_sample.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ldoem::sensor {

// What one beam has become so far on its way through the stages.
struct BeamState {
  raycast::Ray ray;                       // the central ray (D5)
  bool has_return = false;
  double range_m = 0.0;
  double cos_incidence = 1.0;             // of the hit (the strongest sub-ray under mixed_pixels)
  double reflectance = 0.0;
  std::optional<double> irradiance;       // I_rs; set by mixed_pixels or intensity, never otherwise
  std::optional<std::uint16_t> echo;      // set by intensity only
};

// Work done for one beam, so callers and tests can see the cost of the effects (and that a scene
// without noise draws nothing).
struct BeamCounters {
  std::uint64_t rays_cast = 0;
  std::uint64_t random_draws = 0;
};

struct BeamContext {
  const raycast::RayCaster& caster;
  std::uint64_t seed = 0;
  std::uint32_t revolution = 0;
  std::uint32_t beam_index = 0;
};

class BeamStage {
 public:
  virtual ~BeamStage() = default;
  [[nodiscard]] virtual std::string_view name() const = 0;
  // Its parameters as text, for state dumps.
  [[nodiscard]] virtual std::string describe() const = 0;
  virtual void apply(BeamState& beam, const BeamContext& context, BeamCounters& counters) const = 0;
};

// The stages, each constructible alone for tests.
[[nodiscard]] std::unique_ptr<BeamStage> make_single_ray_stage();
// Sub-ray count must be 1, 7, 19 or 37 (hexagonal rings); any other count is rounded down to the
// nearest of these (the scene loader rejects them before they get here).
// `atmosphere`: the extinction every I_rs is multiplied by; nothing (the default) multiplies none.
[[nodiscard]] std::unique_ptr<BeamStage> make_mixed_pixels_stage(
    double beam_divergence_rad, int subray_count, const scene::OpticsConfig& optics, bool use_incidence,
    const std::optional<scene::AtmosphereConfig>& atmosphere = std::nullopt);
[[nodiscard]] std::unique_ptr<BeamStage> make_intensity_stage(
    const scene::OpticsConfig& optics, bool use_incidence,
    const std::optional<scene::AtmosphereConfig>& atmosphere = std::nullopt);
[[nodiscard]] std::unique_ptr<BeamStage> make_noise_stage(const scene::NoiseConfig& noise);
// D13: the footprint's pulses summed into a waveform, one echo detected (stage_waveform.cpp).
[[nodiscard]] std::unique_ptr<BeamStage> make_waveform_stage(
    const scene::ScannerConfig& scanner, bool use_incidence,
    const std::optional<scene::AtmosphereConfig>& atmosphere = std::nullopt);
// D13: noise on the echo's height, probabilistic detection, range sigma from the SNR.
// waveform_thresholds: detection at waveform.threshold_factor * I_rs_min (else at I_rs_min).
[[nodiscard]] std::unique_ptr<BeamStage> make_snr_noise_stage(
    const scene::ScannerConfig& scanner, bool use_incidence,
    const std::optional<scene::AtmosphereConfig>& atmosphere = std::nullopt, bool waveform_thresholds = false);

// Sub-ray count of a hexagonal pattern with `rings` rings around the centre: 1 + 3 k (k + 1).
[[nodiscard]] constexpr int hexagonal_subray_count(int rings) { return 1 + 3 * rings * (rings + 1); }

// Angular offsets (radians, in two perpendicular directions) of the mixed_pixels sub-rays: points
// of a hexagonal lattice whose outer ring's corners lie on the beam's half divergence angle.
[[nodiscard]] std::vector<Eigen::Vector2d> hexagonal_subray_offsets(double beam_divergence_rad,
                                                                    int subray_count);

// How far a beam's ray is cast: a little beyond D_max, so that noise and mixed pixels near D_max
// behave continuously (a target at D_max + 1 mm may still be measured inside the limits).
inline constexpr double kCastMarginBeyondMaxRange_m = 1.0;

class EffectPipeline {
 public:
  [[nodiscard]] static EffectPipeline build(const scene::ScannerConfig& scanner, const scene::EffectSet& effects);

  // One beam through every stage and the encoder. Thread-safe: stages are immutable.
  [[nodiscard]] BeamSample run(const raycast::Ray& ray, const BeamContext& context, BeamCounters& counters) const;

  [[nodiscard]] double cast_range_m() const { return limits_.max_range_m + kCastMarginBeyondMaxRange_m; }
  [[nodiscard]] const RangeLimits& limits() const { return limits_; }
  [[nodiscard]] std::vector<std::string_view> stage_names() const;
  [[nodiscard]] std::string describe() const;

 private:
  EffectPipeline() = default;
  // A scene that names no effect gets one cast and the encoder per beam, with no stage calls:
  // what a scene does not ask for costs nothing (D9).
  [[nodiscard]] BeamSample run_bare(const raycast::Ray& ray, const BeamContext& context,
                                    BeamCounters& counters) const;
  std::vector<std::unique_ptr<const BeamStage>> stages_;
  RangeLimits limits_;
  bool bare_ = false;
};

// The encoder's rule (D3, D6): no return or an out-of-limit range -> {0, 0}; otherwise the
// quantised distance and the echo (kEchoWithoutIntensity when intensity did not run).
[[nodiscard]] BeamSample encode_beam(const BeamState& beam, const RangeLimits& limits);

}  // namespace ldoem::sensor
