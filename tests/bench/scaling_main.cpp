// ldoem_bench_scaling <scene.yaml> <paper|all> <scanners>: what each added scanner costs when
// several share one scene world (one OdeWorld + BVH, plant::SceneWorld), measured below the
// daemon: one plant::ScenePlant per scanner (sensor model, tilt plate, head model), all on this
// one thread, no control unit, telegrams or housings. docs/scaling.md measures the daemon itself
// (ldoem_bench_daemon_scaling, scripts/bench-scaling.sh); this program is not in that report. It
// stays as the physics alone at 14 400 beams/s, a rate no daemon streams (TRANS_MEASURE refuses a
// mean pulse frequency over 10 800 Hz, spec 5).
//
// Load: the device's peak pulse rate, 14 400 beams/s per scanner (20 Hz, 0.5 deg over the
// full 360 deg: 720 beams per revolution), for 2 simulated seconds, every scanner measuring
// every revolution. Printed as one JSON line:
//   cpu_s_per_simulated_s      thread CPU time per simulated second, all scanners together
//   scanners_per_core          scanners / cpu_s_per_simulated_s (what one core sustains in real time)
//   rss_one_mib, rss_all_mib   resident set after the world and the first scanner, after all
//   mib_per_added_scanner      (rss_all - rss_one) / (scanners - 1)
//   heap_mib_per_added_scanner the same from the heap's bytes in use (mallinfo2)
// Measured below the daemon: no control unit, telegram encoding or socket writes (their cost
// per profile is in docs/latency.md); every scanner stands at the scene's pivot.
#include "support/bench_scenes.hpp"
#include "support/process_meters.hpp"

#include <ldoem/plant/scene_plant.hpp>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace {

using ldoem::bench::current_rss_mib;
using ldoem::bench::heap_in_use_mib;
using ldoem::bench::thread_cpu_s;

using namespace ldoem;

constexpr double kRevolutionHz = 20.0;
constexpr int kBeamsPerRevolution = 720;  // 0.5 deg over 360 deg
constexpr std::uint16_t kTicksPerBeam = 8;  // 0.5 deg in 1/16 deg (D5)
constexpr double kSimulatedSeconds = 2.0;

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s scenes/<name>.yaml paper|all <scanners >= 2>\n", argv[0]);
    return 2;
  }
  const std::string effects_name = argv[2];
  const int scanners = std::atoi(argv[3]);
  if ((effects_name != "paper" && effects_name != "all") || scanners < 2) {
    std::fprintf(stderr, "usage: %s scenes/<name>.yaml paper|all <scanners >= 2>\n", argv[0]);
    return 2;
  }
  using scene::Effect;
  const std::vector<Effect> effects =
      effects_name == "paper" ? std::vector<Effect>{Effect::noise, Effect::intensity, Effect::incidence}
                              : std::vector<Effect>{Effect::noise, Effect::intensity, Effect::incidence, Effect::mixed_pixels,
                                                    Effect::motor_dynamics, Effect::head_dynamics, Effect::sweep_motion};
  const scene::Scene scene = bench::with_effects(bench::load_repository_scene(argv[1]), effects);
  plant::SceneWorld world(scene);
  const auto period = std::chrono::duration_cast<base::SimTime>(std::chrono::duration<double>(1.0 / kRevolutionHz));
  std::vector<control::BeamQuery> beams(kBeamsPerRevolution);
  std::vector<control::BeamReturn> returns(kBeamsPerRevolution);
  const auto aim_revolution = [&](int r) {
    const control::RevolutionQuery revolution{static_cast<std::uint64_t>(r + 1), period * r};
    for (int b = 0; b < kBeamsPerRevolution; ++b) {
      const auto ticks = static_cast<std::uint16_t>(b * kTicksPerBeam);
      beams[static_cast<std::size_t>(b)] = {revolution.start + period * ticks / 5760, ticks, ticks};
    }
    return revolution;
  };
  // Memory is read after each scanner has measured one revolution: its per-revolution buffers
  // are grown then, and count as the scanner's.
  const control::RevolutionQuery warm_up = aim_revolution(0);
  std::vector<std::unique_ptr<plant::ScenePlant>> plants;
  plants.push_back(std::make_unique<plant::ScenePlant>(scene, world));
  plants.back()->measurement().measure(warm_up, beams, returns);
  const double rss_one_mib = current_rss_mib();
  const double heap_one_mib = heap_in_use_mib();
  for (int i = 1; i < scanners; ++i) {
    plants.push_back(std::make_unique<plant::ScenePlant>(scene, world));
    plants.back()->measurement().measure(warm_up, beams, returns);
  }
  const double rss_all_mib = current_rss_mib();
  const double heap_all_mib = heap_in_use_mib();

  const int revolutions = static_cast<int>(kSimulatedSeconds * kRevolutionHz);
  std::uint64_t echoes = 0;
  const double cpu_start_s = thread_cpu_s();
  for (int r = 1; r <= revolutions; ++r) {
    const control::RevolutionQuery revolution = aim_revolution(r);
    for (auto& plant : plants) {
      plant->measurement().measure(revolution, beams, returns);
      for (const auto& beam_return : returns) echoes += beam_return.distance_q8_m != 0 ? 1 : 0;
    }
  }
  const double cpu_s = thread_cpu_s() - cpu_start_s;
  const double cpu_per_simulated_s = cpu_s / kSimulatedSeconds;
  std::printf("{\"scene\": \"%s\", \"effects\": \"%s\", \"scanners\": %d, \"beams_per_s_each\": %.0f, "
              "\"echoes\": %llu, \"cpu_s_per_simulated_s\": %.6f, \"scanners_per_core\": %.1f, "
              "\"rss_one_mib\": %.2f, \"rss_all_mib\": %.2f, \"mib_per_added_scanner\": %.4f, "
              "\"heap_mib_per_added_scanner\": %.5f}\n",
              argv[1], effects_name.c_str(), scanners, kRevolutionHz * kBeamsPerRevolution,
              static_cast<unsigned long long>(echoes), cpu_per_simulated_s,
              static_cast<double>(scanners) / cpu_per_simulated_s, rss_one_mib, rss_all_mib,
              (rss_all_mib - rss_one_mib) / static_cast<double>(scanners - 1),
              (heap_all_mib - heap_one_mib) / static_cast<double>(scanners - 1));
  return 0;
}
