// ldoem_bench_motion: what D12 costs and how accurate it is (docs/dynamic-scenes.md,
// docs/accuracy-vs-time.md). Ratios are measured inside one benchmark by interleaved rounds.
//
//   BM_MovingObjects/<index>   rays/s of 100 moving objects against the same scene frozen
//   BM_StaticSceneCost         SensorModel::measure against the measuring loop as it was before D12
//   BM_SkewKnob/<beam_time>    per-beam time against one snapshot per revolution: skew error, cost
//   BM_WorldStep/<step>        ODE world step: falling and rolling trajectory error against cost
//   BM_EditableScene/<scene>   a static scene with a control socket (SceneCaster, no command) against
//                              EmbreeRayCaster alone, and what add/remove-object cost per command
#include "support/bench_scenes.hpp"
#include "support/measure.hpp"

#include <ldoem/raycast/embree_ray_caster.hpp>
#include <ldoem/scene/scene_loader.hpp>
#include <ldoem/sensor/beam_geometry.hpp>
#include <ldoem/sensor/sensor_model.hpp>
#include <ldoem/world/scene_caster.hpp>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>

namespace ldoem::bench {
namespace {

constexpr int kRounds = 5;
constexpr int kMovingRounds = 41;
constexpr double kRevolution_s = 0.1;  // 10 Hz head
constexpr int kBeamsPerRevolution = 1440;  // 0.25 deg

// --- 100 moving objects ------------------------------------------------------------------------

// The random primitive field with every object walking (0.3..1.5 m/s, any heading in the
// plane) and every second one spinning about z (30..180 deg/s): people, carts, doors.
scene::Scene moving_field(std::size_t count) {
  scene::Scene scene = random_primitive_scene(count);
  std::mt19937_64 generator(77);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t k = 0;
  for (auto& object : scene.objects) {
    if (std::holds_alternative<scene::Plane>(object.shape)) continue;
    const double speed = 0.3 + 1.2 * unit(generator);
    const double heading = 2.0 * std::numbers::pi * unit(generator);
    scene::ConstantVelocity velocity;
    velocity.linear_velocity_mps = speed * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
    if (k++ % 2 == 0) velocity.angular_velocity_rad_s.z() = (30.0 + 150.0 * unit(generator)) * std::numbers::pi / 180.0;
    object.motion = velocity;
  }
  return scene;
}

// One revolution per tilt of the paper's range (every 4th layer): each beam at its instant.
std::vector<std::vector<raycast::Ray>> timed_revolutions(const scene::ScannerConfig& scanner) {
  std::vector<std::vector<raycast::Ray>> revolutions;
  for (int layer = 0; layer < kPaperTilt.count; layer += 4) {
    std::vector<raycast::Ray> rays;
    const double start_s = kRevolution_s * static_cast<double>(revolutions.size());
    for (int beam = 0; beam < kBeamsPerRevolution; ++beam) {
      const double fraction = static_cast<double>(beam) / kBeamsPerRevolution;
      raycast::Ray ray = sensor::beam_ray(scanner, 2.0 * std::numbers::pi * fraction, kPaperTilt.angle_rad(layer),
                                          scanner.max_range_m + 1.0);
      ray.time_s = start_s + kRevolution_s * fraction;
      rays.push_back(ray);
    }
    revolutions.push_back(std::move(rays));
  }
  return revolutions;
}

double cast_revolutions(const raycast::RayCaster& caster, world::SceneCaster* moving,
                        const std::vector<std::vector<raycast::Ray>>& revolutions) {
  double sum = 0.0;
  for (const auto& rays : revolutions) {
    if (moving != nullptr) moving->prepare(rays.front().time_s, rays.back().time_s);
    for (const auto& ray : rays) {
      const auto hit = caster.cast(ray);
      if (hit) sum += hit->range_m;
    }
  }
  return sum;
}

// Counters for a ratio taken round by round: its median, quartiles and extremes.
void set_ratio_counters(benchmark::State& state, const std::string& name, const std::vector<double>& ratios) {
  const Spread spread = spread_of(ratios);
  state.counters[name] = spread.median;
  state.counters[name + "_q1"] = spread.lower_quartile;
  state.counters[name + "_q3"] = spread.upper_quartile;
  state.counters[name + "_min"] = spread.min;
  state.counters[name + "_max"] = spread.max;
  state.counters[name + "_rounds"] = static_cast<double>(ratios.size());
}

void bm_moving_objects(benchmark::State& state, raycast::MovingCasterOptions options) {
  const scene::Scene moving = moving_field(100);
  const scene::Scene frozen = random_primitive_scene(100);
  const raycast::OdeWorld frozen_world(frozen);
  const raycast::EmbreeRayCaster frozen_caster(frozen_world);
  world::SceneCaster moving_caster(moving, options);
  const auto revolutions = timed_revolutions(moving.scanner);
  std::size_t rays = 0;
  for (const auto& r : revolutions) rays += r.size();
  // Whole scans (31 revolutions in time order, so that a window reused across revolutions is
  // paid for as it would be), moving then frozen in each short round (a few ms each); the ratio
  // is taken round by round, of the two runs made back to back, and its median reported.
  std::vector<std::vector<double>> times;
  for (auto _ : state) {
    const std::function<void()> jobs[] = {
        [&] { benchmark::DoNotOptimize(cast_revolutions(moving_caster, &moving_caster, revolutions)); },
        [&] { benchmark::DoNotOptimize(cast_revolutions(frozen_caster, nullptr, revolutions)); },
        [&] {
          for (const auto& r : revolutions) moving_caster.prepare(r.front().time_s, r.back().time_s);
        },
    };
    times = interleaved_rounds(jobs, kMovingRounds);
  }
  state.counters["moving_objects"] = static_cast<double>(moving_caster.motion().scene_indices().size());
  state.counters["rays"] = static_cast<double>(rays);
  state.counters["moving_rays_s"] = static_cast<double>(rays) / spread_of(times[0]).median;
  state.counters["frozen_rays_s"] = static_cast<double>(rays) / spread_of(times[1]).median;
  set_ratio_counters(state, "ratio_moving_vs_frozen", round_ratios(times[1], times[0]));
  state.counters["prepare_us_per_revolution"] = 1e6 * spread_of(times[2]).median / static_cast<double>(revolutions.size());
}

// --- A static scene costs what it cost before D12 -------------------------------------------------

// SensorModel::measure's loop as it was before D12 (no pivot_motion test, no time copied), built
// from the same public pieces, so the ratio isolates what D12 added to a static scene's beam.
void measure_before_d12(const scene::Scene& scene, const sensor::SensorModel& model, const raycast::RayCaster& caster,
                        std::uint32_t revolution, std::span<const sensor::BeamRequest> beams,
                        std::span<sensor::BeamSample> out) {
  sensor::BeamCounters counters;
  const double cast_range_m = model.pipeline().cast_range_m();
  for (std::size_t i = 0; i < beams.size(); ++i) {
    const raycast::Ray ray = sensor::beam_ray(scene.scanner, beams[i].head_angle_rad, beams[i].tilt_rad, cast_range_m);
    const sensor::BeamContext context{
        .caster = caster, .seed = scene.seed, .revolution = revolution, .beam_index = beams[i].beam_index};
    out[i] = model.pipeline().run(ray, context, counters);
  }
}

void bm_static_scene_cost(benchmark::State& state, const std::string& path) {
  const scene::Scene scene = load_repository_scene(path);
  const raycast::OdeWorld world(scene);
  const raycast::EmbreeRayCaster caster(world);
  const sensor::SensorModel model(scene, caster);
  std::vector<sensor::BeamRequest> beams;
  for (int layer = 0; layer < kPaperTilt.count; layer += 2) {
    for (std::uint32_t tick = 0; tick < 5760; tick += 4) {
      beams.push_back({tick * 2.0 * std::numbers::pi / 5760.0, kPaperTilt.angle_rad(layer), tick, 0.0});
    }
  }
  std::vector<sensor::BeamSample> now(beams.size());
  std::vector<sensor::BeamSample> before(beams.size());
  std::vector<std::vector<double>> times;
  for (auto _ : state) {
    const std::function<void()> jobs[] = {
        [&] { model.measure(3, beams, now); },
        [&] { measure_before_d12(scene, model, caster, 3, beams, before); },
    };
    times = interleaved_rounds(jobs, 31);
  }
  std::size_t differ = 0;
  for (std::size_t i = 0; i < now.size(); ++i) differ += now[i].distance != before[i].distance || now[i].echo != before[i].echo;
  state.counters["beams"] = static_cast<double>(beams.size());
  set_ratio_counters(state, "ratio_now_vs_before", round_ratios(times[0], times[1]));
  state.counters["samples_that_differ"] = static_cast<double>(differ);
}

// --- A static scene behind a control socket ------------------------------------------------------

// With --control the daemon builds world::SceneCaster even for a static scene, so that objects
// can be added, removed and moved. Without any command it must give the same samples at about
// the same cost; each command rebuilds one index, once.
void bm_editable_scene(benchmark::State& state, const std::string& path) {
  const scene::Scene scene = load_repository_scene(path);
  const raycast::OdeWorld world(scene);
  const raycast::EmbreeRayCaster caster(world);
  const sensor::SensorModel plain(scene, caster);
  world::SceneCaster editable_caster(scene);
  const sensor::SensorModel editable(scene, editable_caster);
  std::vector<std::vector<sensor::BeamRequest>> revolutions;
  for (int layer = 0; layer < kPaperTilt.count; layer += 2) {
    std::vector<sensor::BeamRequest> beams;
    const double start_s = kRevolution_s * static_cast<double>(revolutions.size());
    for (std::uint32_t tick = 0; tick < 5760; tick += 4) {
      beams.push_back({tick * 2.0 * std::numbers::pi / 5760.0, kPaperTilt.angle_rad(layer), tick,
                       start_s + kRevolution_s * tick / 5760.0});
    }
    revolutions.push_back(std::move(beams));
  }
  std::vector<sensor::BeamSample> out(revolutions.front().size());
  std::vector<std::vector<sensor::BeamSample>> with(revolutions.size()), without(revolutions.size());
  std::vector<std::vector<double>> times;
  for (auto _ : state) {
    const std::function<void()> jobs[] = {
        [&] {
          for (std::size_t r = 0; r < revolutions.size(); ++r) {
            editable_caster.prepare(revolutions[r].front().time_s, revolutions[r].back().time_s);
            with[r].resize(out.size());
            editable.measure(3, revolutions[r], with[r]);
          }
        },
        [&] {
          for (std::size_t r = 0; r < revolutions.size(); ++r) {
            without[r].resize(out.size());
            plain.measure(3, revolutions[r], without[r]);
          }
        },
    };
    times = interleaved_rounds(jobs, 15);
  }
  std::size_t differ = 0;
  for (std::size_t r = 0; r < with.size(); ++r) {
    for (std::size_t i = 0; i < with[r].size(); ++i) {
      differ += with[r][i].distance != without[r][i].distance || with[r][i].echo != without[r][i].echo;
    }
  }
  // One command of each kind, timed once each (wall clock; they run on the daemon's loop).
  const auto timed_ms = [](const std::function<void()>& command) {
    const auto start = std::chrono::steady_clock::now();
    command();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  scene::SceneObject crate;
  crate.name = "bench_crate";
  crate.shape = scene::Box{Eigen::Vector3d(0.6, 0.6, 0.6)};
  crate.pose.position_m = Eigen::Vector3d(3, 1, 0);
  scene::SceneObject walker = crate;
  walker.name = "bench_walker";
  walker.motion = scene::ConstantVelocity{Eigen::Vector3d(0, 1, 0), Eigen::Vector3d::Zero()};
  const double at_s = kRevolution_s * static_cast<double>(revolutions.size()) + 1.0;
  // A scene object's removal rebuilds the static index (an epoch); added objects live in the
  // moving index, whose rebuild does not depend on the scene's size.
  const std::string scene_object = scene.objects.front().name;
  state.counters["add_still_ms"] = timed_ms([&] { (void)editable_caster.add_object(crate, at_s); });
  state.counters["add_moving_ms"] = timed_ms([&] { (void)editable_caster.add_object(walker, at_s + 1); });
  state.counters["remove_added_ms"] = timed_ms([&] { (void)editable_caster.remove_object("bench_crate", at_s + 2); });
  state.counters["remove_scene_object_ms"] =
      timed_ms([&] { (void)editable_caster.remove_object(scene_object, at_s + 3); });
  state.counters["static_epochs"] = static_cast<double>(editable_caster.static_epochs());
  state.counters["beams"] = static_cast<double>(out.size() * revolutions.size());
  set_ratio_counters(state, "ratio_editable_vs_plain", round_ratios(times[0], times[1]));
  state.counters["samples_that_differ"] = static_cast<double>(differ);
}

// --- Knob 1: per-beam time against one snapshot per revolution -----------------------------------

constexpr double kWallSpeed_mps = 1.5;  // a walking person
constexpr double kWallStart_m = 8.0;

void bm_skew_knob(benchmark::State& state, scene::BeamTime beam_time) {
  auto loaded = scene::load_scene_from_string(
      "objects:\n  - box: {size_m: [0.2, 30, 30]}\n    pose: {position_m: [8.1, 0, 0]}\n"
      "    motion: {linear_velocity_mps: [-1.5, 0, 0]}\n",
      "generated:approaching-wall");
  const scene::Scene scene = *loaded;
  world::SceneCaster caster(scene);
  // The front half of each revolution (the wall is ahead), 40 revolutions.
  const bool per_beam = beam_time == scene::BeamTime::per_beam;
  double sum_sq = 0.0;
  double max_error = 0.0;
  std::size_t count = 0;
  const auto scan = [&](bool record) {
    for (int revolution = 0; revolution < 40; ++revolution) {
      const double start_s = revolution * kRevolution_s;
      caster.prepare(start_s, start_s + kRevolution_s);
      for (int beam = -kBeamsPerRevolution / 8; beam < kBeamsPerRevolution / 8; ++beam) {
        const double fraction = (beam + kBeamsPerRevolution) % kBeamsPerRevolution / double(kBeamsPerRevolution);
        const double angle = 2.0 * std::numbers::pi * beam / kBeamsPerRevolution;
        const double fires_s = start_s + kRevolution_s * fraction;
        raycast::Ray ray = sensor::beam_ray(scene.scanner, angle, 0.0, 30.0);
        ray.time_s = per_beam ? fires_s : start_s;
        const auto hit = caster.cast(ray);
        if (!record || !hit) continue;
        const double truth = (kWallStart_m - kWallSpeed_mps * fires_s) / std::cos(angle);
        const double error = std::abs(hit->range_m - truth);
        sum_sq += error * error;
        max_error = std::max(max_error, error);
        ++count;
      }
    }
  };
  scan(true);
  std::vector<double> fastest;
  for (auto _ : state) {
    const std::function<void()> jobs[] = {[&] { scan(false); }};
    fastest = fastest_interleaved(jobs, kRounds);
  }
  state.counters["rms_error_mm"] = 1e3 * std::sqrt(sum_sq / static_cast<double>(std::max<std::size_t>(count, 1)));
  state.counters["max_error_mm"] = 1e3 * max_error;
  state.counters["us_per_revolution"] = 1e6 * fastest[0] / 40.0;
}

// --- Knob 2: the ODE world step -----------------------------------------------------------------

scene::Scene bodies_scene(double step_s) {
  auto loaded = scene::load_scene_from_string(
      "world: {world_step_s: " + std::to_string(step_s) + "}\n"
      "objects:\n"
      "  - plane: {normal: [0, 0, 1], offset_m: 0}\n"
      "  - sphere: {radius_m: 0.3}\n    pose: {position_m: [0, 0, 12.3]}\n    dynamics: {mass_kg: 5, restitution: 0}\n"
      "  - sphere: {radius_m: 0.2}\n    pose: {position_m: [3, 0, 0.2]}\n"
      "    dynamics: {mass_kg: 1, initial_velocity_mps: [2, 0, 0], friction: 0.3}\n",
      "generated:fall-and-roll");
  return *loaded;
}

constexpr double kSimulated_s = 1.5;  // the falling ball lands at about 1.56 s

std::vector<Eigen::Vector3d> rolling_track(double step_s) {
  world::RigidBodies bodies(bodies_scene(step_s));
  bodies.advance(0.0, kSimulated_s);
  std::vector<Eigen::Vector3d> track;
  for (int i = 1; i <= 150; ++i) track.push_back(bodies.pose_at(1, i * 0.01).position_m);
  return track;
}

void bm_world_step(benchmark::State& state, double step_s) {
  // Falling: against the closed form. Rolling (sliding into rolling under friction): against the
  // same run at 1e-5 s.
  world::RigidBodies bodies(bodies_scene(step_s));
  bodies.advance(0.0, kSimulated_s);
  double fall_max = 0.0;
  for (int i = 1; i <= 150; ++i) {
    const double t = i * 0.01;
    fall_max = std::max(fall_max, std::abs(bodies.pose_at(0, t).position_m.z() - (12.3 - 0.5 * 9.81 * t * t)));
  }
  static const std::vector<Eigen::Vector3d> reference = rolling_track(1e-5);
  const auto track = rolling_track(step_s);
  double roll_max = 0.0;
  for (std::size_t i = 0; i < track.size(); ++i) roll_max = std::max(roll_max, (track[i] - reference[i]).norm());
  std::vector<double> fastest;
  for (auto _ : state) {
    const std::function<void()> jobs[] = {[&] {
      world::RigidBodies run(bodies_scene(step_s));
      run.advance(0.0, kSimulated_s);
      benchmark::DoNotOptimize(run.pose_at(0, kSimulated_s));
    }};
    fastest = fastest_interleaved(jobs, 3);
  }
  state.counters["fall_max_error_mm"] = 1e3 * fall_max;
  state.counters["roll_max_error_mm"] = 1e3 * roll_max;
  state.counters["cpu_s_per_simulated_s"] = fastest[0] / kSimulated_s;
}

void register_all() {
  using raycast::MovingIndex;
  // <slices>_<window>, "refit": the BVH refitted instead of built afresh per window.
  const std::pair<const char*, raycast::MovingCasterOptions> indices[] = {
      {"slices_1_window_0.3s", {MovingIndex::swept_slices, 1, 0.3, false}},  // the default
      {"slices_1_window_0.3s_refit", {MovingIndex::swept_slices, 1, 0.3, true}},
      {"slices_1_revolution", {MovingIndex::swept_slices, 1, 0.0, false}},
      {"slices_1_revolution_refit", {MovingIndex::swept_slices, 1, 0.0, true}},
      {"slices_1_window_0.5s", {MovingIndex::swept_slices, 1, 0.5, false}},
      {"slices_4_revolution", {MovingIndex::swept_slices, 4, 0.0, false}},
      {"slices_16_revolution", {MovingIndex::swept_slices, 16, 0.0, false}},
      {"blur_4_revolution", {MovingIndex::motion_blur, 4, 0.0, false}},
      {"blur_16_revolution", {MovingIndex::motion_blur, 16, 0.0, false}},
  };
  for (const auto& [name, options] : indices) {
    benchmark::RegisterBenchmark((std::string("BM_MovingObjects/") + name).c_str(), bm_moving_objects, options)
        ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
  }
  for (const char* path : {"scenes/corridor.yaml", "scenes/large.yaml"}) {
    const std::string name = std::string("BM_StaticSceneCost/") + std::filesystem::path(path).stem().string();
    benchmark::RegisterBenchmark(name.c_str(), bm_static_scene_cost, std::string(path))
        ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
  }
  for (const char* path : {"scenes/corridor.yaml", "scenes/large.yaml"}) {
    const std::string name = std::string("BM_EditableScene/") + std::filesystem::path(path).stem().string();
    benchmark::RegisterBenchmark(name.c_str(), bm_editable_scene, std::string(path))
        ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
  }
  benchmark::RegisterBenchmark("BM_SkewKnob/per_beam", bm_skew_knob, scene::BeamTime::per_beam)
      ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
  benchmark::RegisterBenchmark("BM_SkewKnob/per_revolution", bm_skew_knob, scene::BeamTime::per_revolution)
      ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
  for (const auto& [name, step] : {std::pair{"1e-2", 1e-2}, std::pair{"1e-3", 1e-3}, std::pair{"1e-4", 1e-4}}) {
    benchmark::RegisterBenchmark((std::string("BM_WorldStep/") + name).c_str(), bm_world_step, step)
        ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
  }
}

}  // namespace
}  // namespace ldoem::bench

int main(int argc, char** argv) {
  ldoem::bench::register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
