// D12 determinism: the same moving scene and seed give the same samples, twice and whatever the
// number of threads measuring it.
#include "ldoem/sensor/sensor_model.hpp"
#include "world_test_support.hpp"

#include <cstring>
#include <numbers>
#include <thread>

namespace ldoem::world {
namespace {

using testing::scene_from;

const char* const kBusyScene =
    "seed: 7\n"
    "effects: [noise, intensity, mixed_pixels]\n"
    "scanner: {pivot_pose: {position_m: [0, 0, 1]}, pivot_motion: {linear_velocity_mps: [0.3, 0, 0]}}\n"
    "objects:\n"
    "  - plane: {normal: [0, 0, 1], offset_m: 0}\n"
    "  - box: {size_m: [0.5, 0.3, 1.8]}\n"
    "    pose: {position_m: [4, -2, 0.9]}\n"
    "    motion: {linear_velocity_mps: [0, 1.2, 0]}\n"
    "  - box: {size_m: [1, 0.05, 2]}\n"
    "    motion: {interpolation: cubic, loop: true, waypoints: [{t_s: 0, position_m: [-3, 2, 1]},\n"
    "             {t_s: 1, position_m: [-3, 2, 1], rpy_deg: [0, 0, 80]}, {t_s: 2, position_m: [-3, 2, 1]}]}\n"
    "  - sphere: {radius_m: 0.3}\n"
    "    pose: {position_m: [0, 4, 0.3]}\n"
    "    dynamics: {mass_kg: 2, initial_velocity_mps: [1, 0, 0]}\n"
    "  - box: {size_m: [0.6, 0.6, 0.6]}\n"
    "    pose: {position_m: [2, 3, 2.5]}\n"
    "    dynamics: {mass_kg: 10, initial_angular_velocity_dps: [20, 40, 0]}\n";

std::vector<sensor::BeamRequest> revolution_beams(int revolution) {
  std::vector<sensor::BeamRequest> beams;
  for (std::uint32_t tick = 0; tick < 5760; tick += 4) {
    const double angle = tick * 2.0 * std::numbers::pi / 5760.0;
    beams.push_back({angle, 0.05, tick, 0.1 * revolution + 0.1 * tick / 5760.0});
  }
  return beams;
}

std::vector<sensor::BeamSample> scan(int threads) {
  const scene::Scene scene = scene_from(kBusyScene);
  SceneCaster caster(scene);
  const sensor::SensorModel sensor(scene, caster);
  std::vector<sensor::BeamSample> all;
  for (int revolution = 0; revolution < 15; ++revolution) {
    const auto beams = revolution_beams(revolution);
    caster.prepare(beams.front().time_s, beams.back().time_s);
    std::vector<sensor::BeamSample> samples(beams.size());
    const std::size_t per_thread = (beams.size() + threads - 1) / threads;
    std::vector<std::thread> workers;
    for (int t = 0; t < threads; ++t) {
      const std::size_t begin = std::min(beams.size(), t * per_thread);
      const std::size_t end = std::min(beams.size(), begin + per_thread);
      workers.emplace_back([&, begin, end] {
        sensor.measure(static_cast<std::uint32_t>(revolution),
                       std::span(beams).subspan(begin, end - begin), std::span(samples).subspan(begin, end - begin));
      });
    }
    for (auto& worker : workers) worker.join();
    all.insert(all.end(), samples.begin(), samples.end());
  }
  return all;
}

bool same_bytes(const std::vector<sensor::BeamSample>& a, const std::vector<sensor::BeamSample>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].distance != b[i].distance || a[i].echo != b[i].echo) return false;
  }
  return true;
}

TEST(Determinism, SameSceneSameBytesAnyThreadCount) {
  const auto once = scan(1);
  std::size_t echoes = 0;
  for (const auto& s : once) echoes += s.distance != 0;
  EXPECT_GT(echoes, once.size() / 4);
  EXPECT_TRUE(same_bytes(once, scan(1)));
  EXPECT_TRUE(same_bytes(once, scan(2)));
  EXPECT_TRUE(same_bytes(once, scan(5)));
}

// Something really moves: the same beams one second apart see a different scene.
TEST(Determinism, TheWorldChangesWithTime) {
  const auto samples = scan(1);
  const std::size_t per_revolution = 5760 / 4;
  std::size_t differ = 0;
  for (std::size_t i = 0; i < per_revolution; ++i) differ += samples[i].distance != samples[10 * per_revolution + i].distance;
  EXPECT_GT(differ, 50u);
}

}  // namespace
}  // namespace ldoem::world
