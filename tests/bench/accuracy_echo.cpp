#include "accuracy_echo.hpp"

#include "support/bench_scenes.hpp"
#include "support/paper_scan.hpp"

#include <ldoem/raycast/embree_ray_caster.hpp>
#include <ldoem/raycast/ode_world.hpp>
#include <ldoem/sensor/beam_geometry.hpp>
#include <ldoem/sensor/effects.hpp>
#include <ldoem/sensor/sensor_model.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <numbers>

namespace ldoem::bench {
namespace {

using scene::Effect;

const std::vector<Effect> kLightEffects = {Effect::intensity, Effect::incidence};

void time_scans(benchmark::State& state, const scene::Scene& scene) {
  const raycast::OdeWorld world(scene);
  const raycast::EmbreeRayCaster caster(world);
  const sensor::SensorModel sensor(scene, caster);
  for (auto _ : state) benchmark::DoNotOptimize(run_paper_scan(scene, sensor).samples.data());
}

// --- Echo at a depth step ------------------------------------------------------------------------

struct EchoVariant {
  const char* name;
  std::vector<Effect> effects;  // besides intensity and incidence
  scene::EchoDetection detection = scene::EchoDetection::first;
};

const std::vector<EchoVariant> kEchoVariants{
    {"off", {}},
    {"mixed_pixels_7", {Effect::mixed_pixels}},
    {"waveform_first", {Effect::waveform}, scene::EchoDetection::first},
    {"waveform_strongest", {Effect::waveform}, scene::EchoDetection::strongest},
    {"waveform_last", {Effect::waveform}, scene::EchoDetection::last},
};

// The variant's casting stage, with intensity and incidence as in the paper.
std::unique_ptr<sensor::BeamStage> casting_stage(const EchoVariant& variant, const scene::ScannerConfig& scanner) {
  if (variant.name == std::string("off")) return sensor::make_single_ray_stage();
  if (variant.name == std::string("mixed_pixels_7")) {
    return sensor::make_mixed_pixels_stage(scanner.beam_divergence_rad, 7, scanner.optics, true);
  }
  scene::ScannerConfig with_detection = scanner;
  with_detection.waveform.detection = variant.detection;
  return sensor::make_waveform_stage(with_detection, true);
}

struct SurfaceError {
  double rms_mm = 0.0;
  double max_mm = 0.0;
  double mid_air_share = 0.0;  // ranges more than 10 mm from both surfaces
};

// The depth step of BM_MixedPixels (support/bench_scenes.hpp) swept in 60 steps from -1.25 to
// +1.25 half-angles: how far each unquantised range lies from the nearest real surface, along x.
SurfaceError surface_error(const EchoVariant& variant) {
  const scene::Scene step = depth_step_scene(kLightEffects);
  const raycast::OdeWorld world(step);
  const raycast::EmbreeRayCaster caster(world);
  const auto stage = casting_stage(variant, step.scanner);
  const double half_rad = 0.5 * step.scanner.beam_divergence_rad;
  constexpr int kSteps = 60;
  SurfaceError error;
  double sum_squares = 0.0;
  int mid_air = 0;
  for (int i = 0; i < kSteps; ++i) {
    const double offset_rad = (-1.25 + 2.5 * (i + 0.5) / kSteps) * half_rad;
    sensor::BeamState beam;
    beam.ray = sensor::beam_ray(step.scanner, offset_rad, 0.0, 31.0);
    sensor::BeamCounters counters;
    stage->apply(beam, sensor::BeamContext{.caster = caster}, counters);
    const double x_m = beam.has_return ? beam.range_m * beam.ray.direction.x() : 0.0;
    const double error_mm = 1000.0 * std::min(std::abs(x_m - kDepthStepNear_m), std::abs(x_m - kDepthStepWall_m));
    sum_squares += error_mm * error_mm;
    error.max_mm = std::max(error.max_mm, error_mm);
    if (error_mm > 10.0) ++mid_air;
  }
  error.rms_mm = std::sqrt(sum_squares / kSteps);
  error.mid_air_share = static_cast<double>(mid_air) / kSteps;
  return error;
}

void bm_echo_at_edge(benchmark::State& state, const EchoVariant& variant) {
  const SurfaceError error = surface_error(variant);
  scene::Scene corridor = with_effects(load_repository_scene("scenes/corridor.yaml"), plus(kLightEffects, {Effect::noise}));
  for (Effect effect : variant.effects) corridor.effects.add(effect);
  corridor.scanner.waveform.detection = variant.detection;
  time_scans(state, corridor);
  state.counters["surface_rms_mm"] = error.rms_mm;
  state.counters["surface_max_mm"] = error.max_mm;
  state.counters["mid_air_share"] = error.mid_air_share;
}

// --- Range noise ---------------------------------------------------------------------------------

struct NoiseStatistics {
  double sigma_mm = 0.0;
  double detected_share = 0.0;
};

// The noise stages never cast; their context still needs a caster.
class NoCaster final : public raycast::RayCaster {
 public:
  std::optional<raycast::Hit> cast(const raycast::Ray&) const override { return std::nullopt; }
};

// 20000 beams of one stage on a target of reflectance r at `range_m`, head-on.
NoiseStatistics noise_statistics(const sensor::BeamStage& stage, double range_m, double reflectance) {
  constexpr int kCount = 20000;
  const NoCaster no_caster;
  double sum = 0.0;
  double sum_squares = 0.0;
  int detected = 0;
  for (int i = 0; i < kCount; ++i) {
    sensor::BeamState beam;
    beam.has_return = true;
    beam.range_m = range_m;
    beam.reflectance = reflectance;
    sensor::BeamCounters counters;
    stage.apply(beam, sensor::BeamContext{.caster = no_caster, .seed = 2013, .beam_index = static_cast<std::uint32_t>(i)},
                counters);
    if (!beam.has_return) continue;
    sum += beam.range_m;
    sum_squares += beam.range_m * beam.range_m;
    ++detected;
  }
  const double mean = detected > 0 ? sum / detected : 0.0;
  const double variance = detected > 1 ? (sum_squares - detected * mean * mean) / (detected - 1) : 0.0;
  return {1000.0 * std::sqrt(std::max(variance, 0.0)), static_cast<double>(detected) / kCount};
}

void bm_range_noise(benchmark::State& state, Effect model) {
  scene::Scene corridor = with_effects(load_repository_scene("scenes/corridor.yaml"), plus(kLightEffects, {model}));
  const scene::ScannerConfig& scanner = corridor.scanner;
  const auto stage = model == Effect::noise ? sensor::make_noise_stage(scanner.noise)
                                            : sensor::make_snr_noise_stage(scanner, true);
  // The corridor's wall (4.18 m, r 0.75), a dark far target (25 m, r 0.3), and r 0.3 at its D6
  // reach, L sqrt(0.3) = 34.56 m, where the return sits exactly at the threshold.
  const NoiseStatistics wall = noise_statistics(*stage, 4.18, 0.75);
  const NoiseStatistics far = noise_statistics(*stage, 25.0, 0.3);
  const NoiseStatistics at_reach =
      noise_statistics(*stage, scanner.optics.max_range_at_full_reflectance_m * std::sqrt(0.3), 0.3);
  time_scans(state, corridor);
  state.counters["wall_sigma_mm"] = wall.sigma_mm;
  state.counters["far_sigma_mm"] = far.sigma_mm;
  state.counters["at_reach_detected_share"] = at_reach.detected_share;
}

}  // namespace

void register_echo_benchmarks() {
  for (const EchoVariant& variant : kEchoVariants) {
    benchmark::RegisterBenchmark((std::string("BM_EchoAtEdge/") + variant.name).c_str(), bm_echo_at_edge, variant)
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
  }
  for (const auto& [name, model] : {std::pair{"noise", Effect::noise}, std::pair{"snr_noise", Effect::snr_noise}}) {
    benchmark::RegisterBenchmark((std::string("BM_RangeNoise/") + name).c_str(), bm_range_noise, model)
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
  }
}

int write_edge_profile(const std::string& path) {
  const scene::Scene corridor = load_repository_scene("scenes/corridor.yaml");
  const raycast::OdeWorld world(corridor);
  const raycast::EmbreeRayCaster caster(world);
  // The cylinder's left edge seen from the scanner: asin(0.0975 / 2.9) = 1.927 deg; no noise, so
  // the curves show the models alone.
  const std::vector<std::vector<Effect>> variants{
      kLightEffects, plus(kLightEffects, {Effect::mixed_pixels}), plus(kLightEffects, {Effect::waveform})};
  std::vector<std::unique_ptr<scene::Scene>> scenes;
  std::vector<std::unique_ptr<sensor::SensorModel>> sensors;
  for (const auto& effects : variants) {
    scenes.push_back(std::make_unique<scene::Scene>(with_effects(corridor, effects)));
    sensors.push_back(std::make_unique<sensor::SensorModel>(*scenes.back(), caster));
  }
  std::ofstream out(path);
  if (!out) {
    std::fprintf(stderr, "write %s: cannot open\n", path.c_str());
    return 1;
  }
  out << "# head_deg off_m mixed_pixels_m waveform_m (0 = no echo)\n";
  for (int i = 0; i <= 120; ++i) {
    const double head_deg = 1.7 + 0.004 * i;
    const sensor::BeamRequest request{.head_angle_rad = head_deg * std::numbers::pi / 180.0, .tilt_rad = 0.0, .beam_index = 0};
    out << head_deg;
    for (const auto& sensor : sensors) {
      sensor::BeamSample sample;
      sensor->measure(0, std::span(&request, 1), std::span(&sample, 1));
      out << ' ' << sample.distance / sensor::kDistanceUnitsPerMetre;
    }
    out << '\n';
  }
  return out ? 0 : 1;
}

}  // namespace ldoem::bench
