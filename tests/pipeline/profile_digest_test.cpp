// Effects on demand, proven on bytes: every committed scene, measured on a fixed grid of beams
// with each combination of the effects that existed before D13, hashes to the digest recorded on
// main before the D13 effects were added (commit 8ee7987). A D13 change that leaks into a scene
// that does not name its effect changes a digest here.
#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/raycast/ode_world.hpp"
#include "ldoem/scene/scene_loader.hpp"
#include "ldoem/sensor/sensor_model.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "committed_scenes.hpp"

namespace ldoem::sensor {
namespace {

using scene::Effect;

using test::kSceneFiles;
using test::kScenes;

// FNV-1a over the samples' bytes (distance and echo, little-endian): any changed bit shows.
std::uint64_t digest(const std::vector<BeamSample>& samples) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  const auto mix = [&](std::uint16_t word) {
    for (int shift : {0, 8}) {
      hash ^= static_cast<std::uint8_t>(word >> shift);
      hash *= 0x100000001b3ULL;
    }
  };
  for (const BeamSample& sample : samples) {
    mix(sample.distance);
    mix(sample.echo);
  }
  return hash;
}

// Head angles every 1.5 deg all round, tilts every 2 deg over +-10 deg: 2640 beams per scene.
std::vector<BeamSample> measure_grid(const scene::Scene& scene) {
  const raycast::OdeWorld world(scene);
  const raycast::EmbreeRayCaster caster(world);
  const SensorModel model(scene, caster);
  std::vector<BeamSample> all;
  std::uint32_t revolution = 0;
  for (int tilt_deg = -10; tilt_deg <= 10; tilt_deg += 2, ++revolution) {
    std::vector<BeamRequest> beams;
    for (int i = 0; i < 240; ++i) {
      beams.push_back(BeamRequest{.head_angle_rad = (-180.0 + 1.5 * i) * std::numbers::pi / 180.0,
                                  .tilt_rad = tilt_deg * std::numbers::pi / 180.0,
                                  .beam_index = static_cast<std::uint32_t>(i)});
    }
    std::vector<BeamSample> samples(beams.size());
    model.measure(revolution, beams, samples);
    all.insert(all.end(), samples.begin(), samples.end());
  }
  return all;
}

struct EffectCombination {
  const char* name;
  std::vector<Effect> effects;
};

const std::vector<EffectCombination> kPreD13Combinations{
    {"none", {}},
    {"noise", {Effect::noise}},
    {"intensity_incidence", {Effect::intensity, Effect::incidence}},
    {"paper_mixed", {Effect::noise, Effect::intensity, Effect::incidence, Effect::mixed_pixels}},
};

// Recorded on main at 8ee7987 (before D13) with this very grid; key "scene|combination". A
// change to a scene file changes its digests: record them again from a build without D13 (the
// failure message prints each missing or changed line in this form).
const std::map<std::string, std::uint64_t> kRecordedDigests{
    {"corridor.yaml|none", 0xa82da1cc43118eabULL},
    {"corridor.yaml|noise", 0x22a6c00d9ddb56dcULL},
    {"corridor.yaml|intensity_incidence", 0x18a3c85c8f05d561ULL},
    {"corridor.yaml|paper_mixed", 0x15fcde8238d31c4eULL},
    {"minimal.yaml|none", 0x095b2e293b9995dfULL},
    {"minimal.yaml|noise", 0xb108b85f211b4d97ULL},
    {"minimal.yaml|intensity_incidence", 0x34dacacb7b14550cULL},
    {"minimal.yaml|paper_mixed", 0x8ad6f6123dda0f98ULL},
    {"hard/box_edges.yaml|none", 0x72a36cb3433d0875ULL},
    {"hard/box_edges.yaml|noise", 0xa8883980ba0082f0ULL},
    {"hard/box_edges.yaml|intensity_incidence", 0xff2fa7925c7755cdULL},
    {"hard/box_edges.yaml|paper_mixed", 0x64304195e6cd1351ULL},
    {"hard/far_from_origin.yaml|none", 0x653422e9d8779b9bULL},
    {"hard/far_from_origin.yaml|noise", 0x2e17f06d4568e42cULL},
    {"hard/far_from_origin.yaml|intensity_incidence", 0xe672f99eca5be403ULL},
    {"hard/far_from_origin.yaml|paper_mixed", 0x94be4f4210cc7dd2ULL},
    {"hard/grazing_plane.yaml|none", 0xde705aaaece01685ULL},
    {"hard/grazing_plane.yaml|noise", 0x81aa82fad5ec29e6ULL},
    {"hard/grazing_plane.yaml|intensity_incidence", 0x7ea2d3730dcdf1fdULL},
    {"hard/grazing_plane.yaml|paper_mixed", 0x3a4a9005a5eb0319ULL},
    {"hard/mesh_edges.yaml|none", 0x04baebd91362cf5cULL},
    {"hard/mesh_edges.yaml|noise", 0x833c85778c3c7e86ULL},
    {"hard/mesh_edges.yaml|intensity_incidence", 0x72d6f30e7ecf1f14ULL},
    {"hard/mesh_edges.yaml|paper_mixed", 0x8d6960d2d112cd27ULL},
    {"hard/scanner_inside_box.yaml|none", 0x2f474f0200922c05ULL},
    {"hard/scanner_inside_box.yaml|noise", 0x2f4b16a520ac35d8ULL},
    {"hard/scanner_inside_box.yaml|intensity_incidence", 0x2486ab804f2dbaa5ULL},
    {"hard/scanner_inside_box.yaml|paper_mixed", 0x94a2cd7038322d46ULL},
    {"hard/tiny_and_huge.yaml|none", 0x23d9b0eb2fa6f4e2ULL},
    {"hard/tiny_and_huge.yaml|noise", 0xe7efb742271fc4a5ULL},
    {"hard/tiny_and_huge.yaml|intensity_incidence", 0x6184b5500101c985ULL},
    {"hard/tiny_and_huge.yaml|paper_mixed", 0x7464d97d51eaff72ULL},
};

TEST(ProfileDigest, ScenesWithoutD13Effects_MeasureWhatTheyDidBeforeD13) {
  for (const std::string& file : kSceneFiles) {
    auto loaded = scene::load_scene(kScenes / file);
    ASSERT_TRUE(loaded.has_value()) << loaded.error().message();
    for (const EffectCombination& combination : kPreD13Combinations) {
      scene::Scene scene = loaded.value();
      scene.effects = scene::EffectSet{};
      for (Effect effect : combination.effects) scene.effects.add(effect);
      const std::string key = file + "|" + combination.name;
      const std::uint64_t actual = digest(measure_grid(scene));
      char text[32];
      std::snprintf(text, sizeof text, "0x%016llx", static_cast<unsigned long long>(actual));
      const auto recorded = kRecordedDigests.find(key);
      if (recorded == kRecordedDigests.end()) {
        ADD_FAILURE() << "no digest recorded for {\"" << key << "\", " << text << "ULL},";
        continue;
      }
      EXPECT_EQ(actual, recorded->second) << key << ": now " << text;
    }
  }
}

}  // namespace
}  // namespace ldoem::sensor
