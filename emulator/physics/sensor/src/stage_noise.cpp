// D9 noise (D6): range += sigma * G + m, G standard normal from the beam's own counter-based
// stream keyed by (seed, revolution, beam). Only returns are perturbed; a beam without a return
// draws nothing.
#include <ldoem/sensor/effects.hpp>
#include <ldoem/sensor/noise_stream.hpp>

#include <sstream>

namespace ldoem::sensor {
namespace {

class NoiseStage final : public BeamStage {
 public:
  explicit NoiseStage(const scene::NoiseConfig& noise) : noise_(noise) {}

  std::string_view name() const override { return "noise"; }

  std::string describe() const override {
    std::ostringstream text;
    text << "noise: sigma " << noise_.sigma_m << " m, mean " << noise_.mean_m << " m";
    return text.str();
  }

  void apply(BeamState& beam, const BeamContext& context, BeamCounters& counters) const override {
    if (!beam.has_return) return;
    NoiseStream stream(NoiseKey{.seed = context.seed, .revolution = context.revolution,
                                .beam_index = context.beam_index, .sub_stream = 0});
    beam.range_m += noise_.sigma_m * stream.standard_normal() + noise_.mean_m;
    counters.random_draws += stream.draws();
  }

 private:
  scene::NoiseConfig noise_;
};

}  // namespace

std::unique_ptr<BeamStage> make_noise_stage(const scene::NoiseConfig& noise) {
  return std::make_unique<NoiseStage>(noise);
}

}  // namespace ldoem::sensor
