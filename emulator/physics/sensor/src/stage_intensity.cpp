// D9 intensity (+ incidence): Lambert's received irradiance (D6), dropout below I_rs_min, and
// ECHO-n. `incidence` multiplies by cos(alpha); without it the target is lit head-on.
#include "received_power.hpp"

#include <ldoem/sensor/effects.hpp>
#include <ldoem/scene/optics.hpp>

#include <sstream>

namespace ldoem::sensor {
namespace {

class IntensityStage final : public BeamStage {
 public:
  IntensityStage(const scene::OpticsConfig& optics, bool use_incidence,
                 const std::optional<scene::AtmosphereConfig>& atmosphere)
      : optics_(optics), use_incidence_(use_incidence), power_(optics, use_incidence, atmosphere) {}

  std::string_view name() const override { return "intensity"; }

  std::string describe() const override {
    std::ostringstream text;
    text << "intensity: I0 " << optics_.emitted_intensity << ", d " << optics_.receiver_diameter_m
         << " m, I_rs_min " << optics_.min_irradiance << ", calibration " << optics_.calibration
         << ", incidence " << (use_incidence_ ? "on" : "off") << ", extinction " << power_.extinction_per_m()
         << " /m, ECHO scale " << (optics_.echo_scale == scene::EchoScale::log ? "log" : "linear");
    return text.str();
  }

  void apply(BeamState& beam, const BeamContext&, BeamCounters&) const override {
    if (!beam.has_return) return;
    if (!beam.irradiance) {  // mixed_pixels may already have summed its sub-rays' power
      beam.irradiance = power_(beam.reflectance, beam.cos_incidence, beam.range_m);
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
  detail::ReceivedPower power_;
};

}  // namespace

std::unique_ptr<BeamStage> make_intensity_stage(const scene::OpticsConfig& optics, bool use_incidence,
                                                const std::optional<scene::AtmosphereConfig>& atmosphere) {
  return std::make_unique<IntensityStage>(optics, use_incidence, atmosphere);
}

}  // namespace ldoem::sensor
