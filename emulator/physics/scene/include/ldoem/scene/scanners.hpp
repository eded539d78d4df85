// Several scanners in one scene (issue 15): what each scanner's device reads, and the housings
// through which the scanners see each other. docs/scenes.md "Several scanners".
#pragma once

#include "ldoem/scene/scene.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ldoem::scene {

// The scene as scanner `index`'s plant and control unit read it: that scanner's configuration
// and effects, the seed plus `index` (each scanner its own noise streams; the first keeps the
// scene's), the world settings and, for the first scanner only, the scene's faults. It holds no
// objects: the geometry is the shared world's. For a one-scanner scene, index 0 gives the scene's
// own scanner, effects and seed.
[[nodiscard]] Scene scanner_view(const Scene& scene, std::size_t index);

// "scanner" for a one-scanner scene, else the entry's name.
[[nodiscard]] std::string scanner_name(const Scene& scene, std::size_t index);

// With two scanners or more, appends one housing per scanner to scene.objects (a cylinder of
// its HousingConfig about its pivot's z axis, centred on the pivot, moving with pivot_motion)
// and returns each scanner's housing object index; with one scanner it adds nothing and returns
// nothing (a one-scanner scene is unchanged).
std::vector<std::uint32_t> add_housings(Scene& scene);

}  // namespace ldoem::scene
