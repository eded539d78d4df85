// D12 effects on demand: a scene in which nothing moves measures byte for byte what it measured
// before D12 existed. The hashes below were printed by this same file built on main at the commit
// before per-beam time (070a87c) (sensor and casters without time); any change to them is a regression.
#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/scene/scene_loader.hpp"
#include "ldoem/sensor/sensor_model.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

namespace ldoem {
namespace {

// FNV-1a over every sample's DISTANCE and ECHO words, three revolutions at three tilts.
std::uint64_t profile_hash(const std::string& relative_path) {
  const auto scene = scene::load_scene(std::string(LDOEM_SOURCE_DIR) + "/" + relative_path);
  if (!scene) {
    ADD_FAILURE() << scene.error().message();
    return 0;
  }
  const raycast::OdeWorld world(*scene);
  const raycast::EmbreeRayCaster caster(world);
  const sensor::SensorModel sensor(*scene, caster);
  std::uint64_t hash = 1469598103934665603ull;
  const auto mix = [&](std::uint16_t word) {
    for (int shift : {0, 8}) {
      hash ^= (word >> shift) & 0xFFu;
      hash *= 1099511628211ull;
    }
  };
  for (std::uint32_t revolution = 0; revolution < 3; ++revolution) {
    for (double tilt : {-0.2, 0.0, 0.15}) {
      std::vector<sensor::BeamRequest> beams;
      for (std::uint32_t tick = 0; tick < 5760; tick += 4) {
        sensor::BeamRequest beam;
        beam.head_angle_rad = tick * 2.0 * std::numbers::pi / 5760.0;
        beam.tilt_rad = tilt;
        beam.beam_index = tick;
        beams.push_back(beam);
      }
      std::vector<sensor::BeamSample> samples(beams.size());
      sensor.measure(revolution, beams, samples);
      for (const auto& s : samples) {
        mix(s.distance);
        mix(s.echo);
      }
    }
  }
  std::printf("%s 0x%016llx\n", relative_path.c_str(), static_cast<unsigned long long>(hash));
  return hash;
}

TEST(StaticScenes, ProfilesAreByteIdenticalToBeforeD12) {
  EXPECT_EQ(profile_hash("scenes/minimal.yaml"), 0x355b210b8cfd7d54ull);
  EXPECT_EQ(profile_hash("scenes/corridor.yaml"), 0xc101c4b361b9ed18ull);
  EXPECT_EQ(profile_hash("scenes/large.yaml"), 0x16e040670e908024ull);
  EXPECT_EQ(profile_hash("scenes/hard/box_edges.yaml"), 0x2687981889e46b85ull);
  EXPECT_EQ(profile_hash("scenes/hard/mesh_edges.yaml"), 0xfc4bf0d5e3466b71ull);
}

}  // namespace
}  // namespace ldoem
