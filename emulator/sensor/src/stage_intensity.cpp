// D9 intensity (+ incidence): Lambert's received irradiance (D6), dropout below I_rs_min, and
// ECHO-n. `incidence` multiplies by cos(alpha); without it the target is lit head-on.
#include <ldoem/sensor/effects.hpp>
#include <ldoem/scene/optics.hpp>

#include <sstream>

namespace ldoem::sensor {
namespace {

class IntensityStage final : public BeamStage {
 public:
  IntensityStage(const scene::OpticsConfig& optics, bool use_incidence)
      : optics_(optics), use_incidence_(use_incidence) {}

  std::string_view name() const override { return "intensity"; }

  std::string describe() const override {
    std::ostringstream text;
    text << "intensity: I0 " << optics_.emitted_intensity << ", d " << optics_.receiver_diameter_m
         << " m, I_rs_min " << optics_.min_irradiance << ", calibration " << optics_.calibration
         << ", incidence " << (use_incidence_ ? "on" : "off");
    return text.str();
  }

  void apply(BeamState& beam, const BeamContext&, BeamCounters&) const override {
    if (!beam.has_return) return;
    if (!beam.irradiance) {  // mixed_pixels may already have summed its sub-rays' power
      beam.irradiance = scene::received_irradiance(optics_, beam.reflectance,
                                            use_incidence_ ? beam.cos_incidence : 1.0, beam.range_m);
    }
    if (!(*beam.irradiance >= optics_.min_irradiance)) {  // D6 dropout; NaN drops out too
      beam.has_return = false;
      return;
    }
    beam.echo = scene::echo_value(optics_, *beam.irradiance);
  }

 private:
  scene::OpticsConfig optics_;
  bool use_incidence_;
};

}  // namespace

std::unique_ptr<BeamStage> make_intensity_stage(const scene::OpticsConfig& optics, bool use_incidence) {
  return std::make_unique<IntensityStage>(optics, use_incidence);
}

}  // namespace ldoem::sensor
