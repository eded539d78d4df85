#include "hit_geometry.hpp"

#include <ldoem/sensor/effects.hpp>

namespace ldoem::sensor {

using scene::Effect;

EffectPipeline EffectPipeline::build(const scene::ScannerConfig& scanner, const scene::EffectSet& effects) {
  EffectPipeline pipeline;
  pipeline.limits_ = RangeLimits{.min_range_m = scanner.min_range_m, .max_range_m = scanner.max_range_m};
  const bool use_incidence = effects.has(Effect::incidence);
  const std::optional<scene::AtmosphereConfig> atmosphere =
      effects.has(Effect::atmosphere) ? std::optional(scanner.atmosphere) : std::nullopt;
  // The fixed order of docs/sensor-model.md; it does not follow the order of the YAML keys.
  // D13: waveform replaces mixed_pixels' weighted mean (it casts the same footprint).
  if (effects.has(Effect::waveform)) {
    pipeline.stages_.push_back(make_waveform_stage(scanner, use_incidence, atmosphere));
  } else if (effects.has(Effect::mixed_pixels)) {
    pipeline.stages_.push_back(make_mixed_pixels_stage(scanner.beam_divergence_rad, scanner.mixed_pixel_subrays,
                                                       scanner.optics, use_incidence, atmosphere));
  } else {
    pipeline.stages_.push_back(make_single_ray_stage());
  }
  if (effects.has(Effect::snr_noise)) {
    pipeline.stages_.push_back(
        make_snr_noise_stage(scanner, use_incidence, atmosphere, effects.has(Effect::waveform)));
  }
  if (effects.has(Effect::intensity)) {
    pipeline.stages_.push_back(make_intensity_stage(scanner.optics, use_incidence, atmosphere));
  }
  if (effects.has(Effect::noise)) pipeline.stages_.push_back(make_noise_stage(scanner.noise));
  pipeline.bare_ = pipeline.stages_.size() == 1 && pipeline.stages_.front()->name() == "single_ray";
  return pipeline;
}

BeamSample EffectPipeline::run(const raycast::Ray& ray, const BeamContext& context, BeamCounters& counters) const {
  if (bare_) return run_bare(ray, context, counters);
  BeamState beam;
  beam.ray = ray;
  for (const auto& stage : stages_) stage->apply(beam, context, counters);
  return encode_beam(beam, limits_);
}

BeamSample EffectPipeline::run_bare(const raycast::Ray& ray, const BeamContext& context,
                                    BeamCounters& counters) const {
  ++counters.rays_cast;
  const std::optional<raycast::Hit> hit = context.caster.cast(ray);
  if (!hit || !detail::usable_hit(*hit)) return {};
  const std::optional<std::uint16_t> distance = quantise_range(hit->range_m, limits_);
  if (!distance) return {};
  return BeamSample{.distance = *distance, .echo = kEchoWithoutIntensity};
}

std::vector<std::string_view> EffectPipeline::stage_names() const {
  std::vector<std::string_view> names;
  for (const auto& stage : stages_) names.push_back(stage->name());
  return names;
}

std::string EffectPipeline::describe() const {
  std::string text;
  for (const auto& stage : stages_) text += stage->describe() + "\n";
  text += "encode: 1/256 m, D_min " + std::to_string(limits_.min_range_m) + " m, D_max " +
          std::to_string(limits_.max_range_m) + " m\n";
  return text;
}

BeamSample encode_beam(const BeamState& beam, const RangeLimits& limits) {
  if (!beam.has_return) return {};
  const std::optional<std::uint16_t> distance = quantise_range(beam.range_m, limits);
  if (!distance) return {};
  return BeamSample{.distance = *distance, .echo = beam.echo.value_or(kEchoWithoutIntensity)};
}

}  // namespace ldoem::sensor
