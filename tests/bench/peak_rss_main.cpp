// ldoem_bench_rss <scene.yaml relative to the source tree>: peak resident memory of loading a
// scene, building the ODE geoms and the Embree caster, and casting the D4 sector (270 deg at
// 0.25 deg) at every layer of the paper's tilt range, printed beside that cast's throughput.
// One scene per process, because ru_maxrss is a process's high-water mark.
#include "support/bench_scenes.hpp"
#include "support/measure.hpp"

#include <ldoem/raycast/embree_ray_caster.hpp>
#include <ldoem/raycast/ode_world.hpp>

#include <chrono>
#include <cstdio>

int main(int argc, char** argv) {
  using namespace ldoem;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s scenes/<name>.yaml\n", argv[0]);
    return 2;
  }
  const double rss_at_start_mib = bench::peak_rss_mib();
  const scene::Scene scene = bench::load_repository_scene(argv[1]);
  const raycast::OdeWorld world(scene);
  const raycast::EmbreeRayCaster caster(world);
  const auto rays = bench::scanner_rays(scene.scanner, bench::kFullSectorHead, bench::kPaperTilt,
                                        scene.scanner.max_range_m + 1.0);
  const auto start = std::chrono::steady_clock::now();
  std::size_t hits = 0;
  for (const auto& ray : rays) hits += caster.cast(ray).has_value() ? 1 : 0;
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  std::printf("{\"scene\": \"%s\", \"objects\": %zu, \"rays\": %zu, \"hits\": %zu, \"rays_per_s\": %.0f, "
              "\"peak_rss_mib\": %.1f, \"rss_at_start_mib\": %.1f}\n",
              argv[1], scene.objects.size(), rays.size(), hits, static_cast<double>(rays.size()) / elapsed.count(),
              bench::peak_rss_mib(), rss_at_start_mib);
  return 0;
}
