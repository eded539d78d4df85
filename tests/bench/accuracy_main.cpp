// ldoem_bench_accuracy: what accuracy costs in time (docs/accuracy-vs-time.md). Each benchmark's
// time is one paper scan of the corridor (support/paper_scan.hpp) with one knob set; its error
// is measured once, in the set-up, against a reference that does not depend on the knob:
//
//   BM_MotorModel/<model>   tilt of every beam against the ideal step grid (sweep_motion on)
//   BM_MixedPixels/<n>      range at a depth step against the analytic footprint average
//   BM_Cylinder/<mesh>      fitted diameter of the 195 mm cylinder, exact primitive or mesh
//   BM_EffectCost           per-beam cost of each D9 effect, interleaved rounds (measure.hpp)
//   BM_EchoAtEdge, BM_RangeNoise: the D13 rows (accuracy_echo.hpp)
// `--edge-profile=FILE` writes the cylinder-edge profile the report plots instead.
#include "accuracy_echo.hpp"
#include "support/bench_scenes.hpp"
#include "support/measure.hpp"
#include "support/paper_scan.hpp"

#include <ldoem/cloud/fitting.hpp>
#include <ldoem/motor/tilt_motor.hpp>
#include <ldoem/raycast/embree_ray_caster.hpp>
#include <ldoem/raycast/ode_world.hpp>
#include <ldoem/sensor/beam_geometry.hpp>
#include <ldoem/sensor/effects.hpp>
#include <ldoem/sensor/sensor_model.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

namespace ldoem::bench {
namespace {

using scene::Effect;

const std::vector<Effect> kPaperEffects = {Effect::noise, Effect::intensity, Effect::incidence};

void configure(benchmark::internal::Benchmark* benchmark) { benchmark->UseRealTime()->Unit(benchmark::kMillisecond); }

void time_scans(benchmark::State& state, const scene::Scene& scene, const sensor::SensorModel& sensor) {
  std::uint64_t beams = 0;
  for (auto _ : state) {
    const PaperScanResult scan = run_paper_scan(scene, sensor);
    beams += scan.beams.size();
    benchmark::DoNotOptimize(scan.samples.data());
  }
  state.counters["beams_per_scan"] = static_cast<double>(beams) / static_cast<double>(state.iterations());
}

// --- Motor model ----------------------------------------------------------------------------

// One layer move alone (2 full-step pulses at the scan's rate, from rest), sampled every 0.1 ms
// for 200 ms: the largest lag behind the commanded position, and when the plate last was more
// than 1 mdeg from the target. What the scan's beams would see if they came during the move.
struct MoveResponse {
  double max_lag_mdeg = 0.0;
  double settle_ms = 0.0;
};

MoveResponse layer_move_response(const scene::Scene& scene) {
  using namespace std::chrono_literals;
  constexpr double kMillidegreesPerRad = 180.0e3 / std::numbers::pi;
  const auto tilt_motor = motor::make_tilt_motor(scene);
  const PaperScanOptions options;
  const double full_step_rad = 2.0 * motor::half_step_rad(scene.scanner.tilt_motor);
  const base::SimTime start = 1s;
  const base::SimTime pulse_interval =
      std::chrono::duration_cast<base::SimTime>(std::chrono::duration<double>(1.0 / options.step_rate_hz));
  const base::SimTime pulses[] = {start, start + pulse_interval};
  tilt_motor->advance_to(start - 1ms);
  MoveResponse response;
  std::size_t sent = 0;
  for (base::SimTime t = start - 1ms; t <= start + 200ms; t += 100us) {
    while (sent < std::size(pulses) && pulses[sent] <= t) tilt_motor->on_step_pulse(pulses[sent++], 1, false);
    tilt_motor->advance_to(t);
    const double lag_mdeg = std::abs(tilt_motor->tilt_rad() - static_cast<double>(sent) * full_step_rad) * kMillidegreesPerRad;
    response.max_lag_mdeg = std::max(response.max_lag_mdeg, lag_mdeg);
    const double off_target_mdeg = std::abs(tilt_motor->tilt_rad() - 2.0 * full_step_rad) * kMillidegreesPerRad;
    if (off_target_mdeg > 1.0) response.settle_ms = std::chrono::duration<double, std::milli>(t - start).count();
  }
  return response;
}

// world_step_s <= 0: the ideal motor.
void bm_motor_model(benchmark::State& state, double world_step_s) {
  scene::Scene corridor = load_repository_scene("scenes/corridor.yaml");
  std::vector<Effect> effects = plus(kPaperEffects, {Effect::sweep_motion});
  if (world_step_s > 0.0) {
    effects.push_back(Effect::motor_dynamics);
    corridor.scanner.tilt_motor.world_step_s = world_step_s;
  }
  corridor = with_effects(corridor, effects);
  const raycast::OdeWorld world(corridor);
  const raycast::EmbreeRayCaster caster(world);
  const sensor::SensorModel sensor(corridor, caster);
  const TiltError error = tilt_error(run_paper_scan(corridor, sensor));
  const MoveResponse move = layer_move_response(corridor);
  time_scans(state, corridor, sensor);
  state.counters["move_max_lag_mdeg"] = move.max_lag_mdeg;
  state.counters["move_settle_ms"] = move.settle_ms;
  constexpr double kMillidegreesPerRad = 180.0e3 / std::numbers::pi;
  state.counters["tilt_rms_mdeg"] = error.rms_rad * kMillidegreesPerRad;
  state.counters["tilt_max_mdeg"] = error.max_rad * kMillidegreesPerRad;
  // The same error as a height error of the point on the corridor's wall, 4.18 m away.
  state.counters["wall_height_rms_mm"] = error.rms_rad * 4180.0;
}

// --- Mixed pixels at a depth step -------------------------------------------------------------

// The depth step (support/bench_scenes.hpp): near face at 2.8 m (r 0.6), wall at 4.18 m (0.75).
constexpr double kNearFace_m = kDepthStepNear_m;
constexpr double kWallFace_m = kDepthStepWall_m;
constexpr double kNearReflectance = kDepthStepNearReflectance;
constexpr double kWallReflectance = kDepthStepWallReflectance;

// The model's continuum limit (docs/sensor-model.md: a top-hat beam, each part of the cross-
// section weighted by its D6 irradiance r cos(alpha) / l^2): the share f of the disc of angular
// radius a on the near side of the edge (a circular segment) weighted against the rest. Ranges
// and cosines are taken at the cone's axis: within a = 1.25 mrad they vary by under 3e-6
// relative (12 um at the wall), far below the errors measured here.
double analytic_edge_range_m(double beam_offset_rad, double half_divergence_rad) {
  const double a = half_divergence_rad;
  const double c = std::clamp(beam_offset_rad, -a, a);
  // Disc points with u > -c: a^2 acos(-c/a) + c sqrt(a^2 - c^2), over the disc's area.
  const double near_share = (a * a * std::acos(-c / a) + c * std::sqrt(a * a - c * c)) / (std::numbers::pi * a * a);
  const double near_weight = near_share * kNearReflectance / (kNearFace_m * kNearFace_m);
  const double wall_weight = (1.0 - near_share) * kWallReflectance / (kWallFace_m * kWallFace_m);
  return (near_weight * kNearFace_m + wall_weight * kWallFace_m) / (near_weight + wall_weight);
}

struct EdgeError {
  double rms_mm = 0.0;
  double max_mm = 0.0;
};

// The beam swept across the edge in 60 steps from -1.25 a to +1.25 a (never exactly on it);
// the stage's unquantised range against the analytic one (quantisation to 1/256 m would add
// up to 1.95 mm that has nothing to do with the knob).
EdgeError edge_error(int subrays) {
  const scene::Scene step = depth_step_scene({Effect::mixed_pixels, Effect::intensity, Effect::incidence});
  const raycast::OdeWorld world(step);
  const raycast::EmbreeRayCaster caster(world);
  const double divergence_rad = step.scanner.beam_divergence_rad;
  const auto stage = sensor::make_mixed_pixels_stage(divergence_rad, subrays, step.scanner.optics, true);
  constexpr int kSteps = 60;
  double sum_squares = 0.0;
  EdgeError error;
  for (int i = 0; i < kSteps; ++i) {
    const double offset_rad = (-1.25 + 2.5 * (i + 0.5) / kSteps) * 0.5 * divergence_rad;
    sensor::BeamState beam;
    beam.ray = sensor::beam_ray(step.scanner, offset_rad, 0.0, 31.0);
    const sensor::BeamContext context{.caster = caster, .seed = 1, .revolution = 0, .beam_index = 0};
    sensor::BeamCounters counters;
    stage->apply(beam, context, counters);
    const double error_mm =
        1000.0 * ((beam.has_return ? beam.range_m : 0.0) - analytic_edge_range_m(offset_rad, 0.5 * divergence_rad));
    sum_squares += error_mm * error_mm;
    error.max_mm = std::max(error.max_mm, std::abs(error_mm));
  }
  error.rms_mm = std::sqrt(sum_squares / kSteps);
  return error;
}

// subrays 0: mixed_pixels not named (one ray per beam).
void bm_mixed_pixels(benchmark::State& state, int subrays) {
  scene::Scene corridor = load_repository_scene("scenes/corridor.yaml");
  corridor.scanner.mixed_pixel_subrays = std::max(1, subrays);
  corridor = with_effects(corridor, subrays > 0 ? plus(kPaperEffects, {Effect::mixed_pixels}) : kPaperEffects);
  const raycast::OdeWorld world(corridor);
  const raycast::EmbreeRayCaster caster(world);
  const sensor::SensorModel sensor(corridor, caster);
  const EdgeError error = edge_error(std::max(1, subrays));
  time_scans(state, corridor, sensor);
  state.counters["edge_rms_mm"] = error.rms_mm;
  state.counters["edge_max_mm"] = error.max_mm;
}

// --- Exact cylinder against meshes ------------------------------------------------------------

constexpr double kCylinderDiameter_m = 0.195;

// The corridor's cylinder stands at (2.9, 0) from z = 0 to 0.998 m: keep points near its axis,
// off the floor and below its top cap, and fit a cylinder about z.
std::optional<double> fitted_diameter_m(const std::vector<Eigen::Vector3d>& points, double inlier_m) {
  std::vector<Eigen::Vector3d> near_cylinder;
  for (const Eigen::Vector3d& p : points) {
    if (std::hypot(p.x() - 2.9, p.y()) < 0.3 && p.z() > 0.05 && p.z() < 0.95) near_cylinder.push_back(p);
  }
  cloud::CylinderRansacOptions options;
  options.inlier_distance_m = inlier_m;
  options.iterations = 500;
  options.axis_hint = cloud::AxisHint{Eigen::Vector3d::UnitZ(), 0.1};
  options.min_radius_m = 0.05;
  options.max_radius_m = 0.2;
  const auto fit = cloud::fit_cylinder_ransac(near_cylinder, options);
  if (!fit) return std::nullopt;
  return 2.0 * fit->radius_m;
}

// Noise-free and unquantised: every paper-scan beam cast straight at the caster.
std::vector<Eigen::Vector3d> geometric_points(const scene::Scene& scene, const raycast::RayCaster& caster) {
  std::vector<Eigen::Vector3d> points;
  for (const raycast::Ray& ray : scanner_rays(scene.scanner, kPaperHead, kPaperTilt, 31.0)) {
    if (const auto hit = caster.cast(ray)) points.push_back(ray.origin_m + hit->range_m * ray.direction);
  }
  return points;
}

// triangles 0: the exact primitive.
void bm_cylinder(benchmark::State& state, int triangles) {
  const scene::Scene corridor =
      with_effects(corridor_with_cylinder(load_repository_scene("scenes/corridor.yaml"), triangles), kPaperEffects);
  const raycast::OdeWorld world(corridor);
  const auto build_start = std::chrono::steady_clock::now();
  const raycast::EmbreeRayCaster caster(world);
  const std::chrono::duration<double, std::milli> build_ms = std::chrono::steady_clock::now() - build_start;
  const sensor::SensorModel sensor(corridor, caster);
  const auto scanned = fitted_diameter_m(scan_points(corridor.scanner, run_paper_scan(corridor, sensor)), 0.006);
  const auto geometric = fitted_diameter_m(geometric_points(corridor, caster), 0.003);
  time_scans(state, corridor, sensor);
  state.counters["triangles"] = triangles;
  state.counters["build_ms"] = build_ms.count();
  // A failed fit has no error to report: its counters say so (the report prints "fit failed"),
  // never a made-up diameter.
  state.counters["scan_fit_ok"] = scanned ? 1.0 : 0.0;
  state.counters["geometric_fit_ok"] = geometric ? 1.0 : 0.0;
  state.counters["scan_diameter_error_mm"] = scanned ? 1000.0 * (*scanned - kCylinderDiameter_m) : 0.0;
  state.counters["geometric_diameter_error_mm"] = geometric ? 1000.0 * (*geometric - kCylinderDiameter_m) : 0.0;
}

// --- Per-effect cost ---------------------------------------------------------------------------

struct EffectVariant {
  std::string name;
  std::vector<Effect> effects;
};

void bm_effect_cost(benchmark::State& state) {
  const scene::Scene corridor = load_repository_scene("scenes/corridor.yaml");
  const raycast::OdeWorld world(corridor);
  const raycast::EmbreeRayCaster caster(world);
  const std::vector<EffectVariant> variants = {
      {"none", {}},
      {"noise", {Effect::noise}},
      {"intensity", {Effect::intensity}},
      {"intensity_incidence", {Effect::intensity, Effect::incidence}},
      {"mixed_pixels_7", {Effect::mixed_pixels}},
      {"motor_dynamics", {Effect::motor_dynamics}},
      {"head_dynamics", {Effect::head_dynamics}},
      {"sweep_motion", {Effect::sweep_motion}},
      {"waveform", {Effect::waveform}},
      {"snr_noise", {Effect::snr_noise}},
      {"intensity_atmosphere", {Effect::intensity, Effect::atmosphere}},
      {"paper", kPaperEffects},
      {"all", plus(kPaperEffects, {Effect::mixed_pixels, Effect::motor_dynamics, Effect::head_dynamics,
                                   Effect::sweep_motion})},
  };
  std::vector<scene::Scene> scenes;
  for (const auto& variant : variants) scenes.push_back(with_effects(corridor, variant.effects));
  std::vector<std::unique_ptr<sensor::SensorModel>> sensors;
  for (const auto& s : scenes) sensors.push_back(std::make_unique<sensor::SensorModel>(s, caster));
  std::vector<std::function<void()>> jobs;
  for (std::size_t v = 0; v < variants.size(); ++v) {
    jobs.emplace_back([&, v] { benchmark::DoNotOptimize(run_paper_scan(scenes[v], *sensors[v]).samples.data()); });
  }
  const double beams = static_cast<double>(run_paper_scan(scenes[0], *sensors[0]).beams.size());
  std::vector<double> fastest;
  for (auto _ : state) fastest = fastest_interleaved(jobs, 21);
  for (std::size_t v = 0; v < variants.size(); ++v) {
    state.counters[variants[v].name + "_ns_per_beam"] = 1e9 * fastest[v] / beams;
  }
}

void register_all() {
  const std::pair<const char*, double> motors[] = {
      {"ideal", 0.0}, {"dynamic_1e-2", 1e-2}, {"dynamic_1e-3", 1e-3}, {"dynamic_1e-4", 1e-4}};
  for (const auto& [name, step_s] : motors) {
    configure(benchmark::RegisterBenchmark((std::string("BM_MotorModel/") + name).c_str(), bm_motor_model, step_s));
  }
  for (const int subrays : {0, 1, 7, 19, 37}) {
    const std::string name = subrays == 0 ? "off" : std::to_string(subrays);
    configure(benchmark::RegisterBenchmark(("BM_MixedPixels/" + name).c_str(), bm_mixed_pixels, subrays));
  }
  for (const int triangles : {0, 64, 1024, 16384, 262144}) {
    const std::string name = triangles == 0 ? "exact" : std::to_string(triangles);
    configure(benchmark::RegisterBenchmark(("BM_Cylinder/" + name).c_str(), bm_cylinder, triangles));
  }
  register_echo_benchmarks();
  benchmark::RegisterBenchmark("BM_EffectCost", bm_effect_cost)->Iterations(1)->Unit(benchmark::kMillisecond);
}

}  // namespace
}  // namespace ldoem::bench

int main(int argc, char** argv) {
  const std::string_view edge_profile_flag = "--edge-profile=";
  for (int i = 1; i < argc; ++i) {
    const std::string_view argument = argv[i];
    if (argument.starts_with(edge_profile_flag)) {
      return ldoem::bench::write_edge_profile(std::string(argument.substr(edge_profile_flag.size())));
    }
  }
  ldoem::bench::register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
