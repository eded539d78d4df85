// Bytes -> a small scene and a batch of rays aimed where casters break (issue 26): coincident
// and nearly coincident faces, rays through edges and vertices, grazing by 1e-15..1e-3 rad,
// origins on or a few ulps off surfaces, scales 1e-6..1e5 m, scenes 1e6 m from the origin,
// degenerate and sliver triangles, reaches ending at the surface, scanner housings the rays
// leave from. The differential fuzzer feeds it libFuzzer's bytes, the seeded sweep random ones.
//
// Format: byte 0 bit 0 set = the scene is given explicitly (encode_scene, the seeds written
// from scenes/hard/), else it is generated from the following bytes; the rest chooses rays.
// Any byte string is a valid case (short input reads as zeros).
#pragma once

#include "ldoem/raycast/ray_caster.hpp"
#include "ldoem/scene/scene.hpp"

#include <cstdint>
#include <span>
#include <vector>

namespace ldoem::oracle {

struct OracleCase {
  scene::Scene scene;
  std::vector<raycast::Ray> rays;  // ignored_object set for rays from inside a housing
};

OracleCase make_case(std::span<const std::uint8_t> bytes);

// The explicit form of `scene`'s objects (meshes with at most 64 triangles), followed by
// `ray_bytes` bytes of ray choices: the seed corpus is written with it.
std::vector<std::uint8_t> encode_scene(const scene::Scene& scene, std::span<const std::uint8_t> ray_bytes);

}  // namespace ldoem::oracle
