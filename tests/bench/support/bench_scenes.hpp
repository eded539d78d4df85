// Scenes and ray sets the benchmarks share: the repository's scenes, random primitive fields of a
// given size, the corridor with its cylinder replaced by a mesh, and the scanner's ray patterns.
#pragma once

#include <ldoem/raycast/ray_caster.hpp>
#include <ldoem/scene/scene.hpp>

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

namespace ldoem::bench {

// The source tree (LDOEM_SOURCE_DIR at build time, or the environment variable of that name).
[[nodiscard]] std::filesystem::path source_dir();

// load_scene on a path relative to the source tree; prints the error and exits on failure
// (benchmark programs have nobody to hand a typed error to).
[[nodiscard]] scene::Scene load_repository_scene(const std::string& relative_path);

// `count` boxes, spheres, cylinders and capsules (in turn) at random poses in a ring 2..15 m
// around the scanner, 0..2 m high, sizes 0.1..0.6 m, and a floor plane. Fixed seed: the same
// scene on every run.
[[nodiscard]] scene::Scene random_primitive_scene(std::size_t count, std::uint64_t seed = 2013);

// Only the objects whose shape is a mesh or a plane (the 100k-triangle rock of large.yaml).
[[nodiscard]] scene::Scene meshes_and_planes_only(const scene::Scene& scene);

// The corridor with the object named "cylinder" replaced by a tessellated copy of itself with
// `triangles` triangles (64, 1024, 16384 or 262144); 0 keeps the exact primitive.
[[nodiscard]] scene::Scene corridor_with_cylinder(const scene::Scene& corridor, int triangles);

// Two parallel surfaces facing the scanner (both normal to x): the near face of a box covering
// y >= 0 at x = 2.8 m, and a wall at x = 4.18 m (the corridor's cylinder and wall distances).
// The edge lies in the plane y = 0, which contains the optical centre, so seen from the scanner
// it is a straight line through the beam's cross-section and no side face is ever hit.
inline constexpr double kDepthStepNear_m = 2.8;
inline constexpr double kDepthStepWall_m = 4.18;
inline constexpr double kDepthStepNearReflectance = 0.6;
inline constexpr double kDepthStepWallReflectance = 0.75;
[[nodiscard]] scene::Scene depth_step_scene(const std::vector<scene::Effect>& effects);

// The scene with exactly these D9 effects.
[[nodiscard]] scene::Scene with_effects(scene::Scene scene, const std::vector<scene::Effect>& effects);

// `effects` with `more` appended: an effect list and one or two effects on top of it.
[[nodiscard]] std::vector<scene::Effect> plus(std::vector<scene::Effect> effects, std::initializer_list<scene::Effect> more);

// Rays of the scanner for a grid of head angles and tilts (D5), each cast to max_range_m.
struct AngleGrid {
  double first_deg;
  double step_deg;
  int count;
  [[nodiscard]] double angle_rad(int i) const;
};
[[nodiscard]] std::vector<raycast::Ray> scanner_rays(const scene::ScannerConfig& scanner, const AngleGrid& head,
                                                     const AngleGrid& tilt, double max_range_m);

// The paper's scan (Koceski & Koceska 2013): horizontal apex 20 deg at 0.25 deg (81 beams),
// vertical apex 21.6 deg at 0.18 deg = 2 full steps (121 layers, -10.8 .. +10.8 deg).
inline constexpr AngleGrid kPaperHead{-10.0, 0.25, 81};
inline constexpr AngleGrid kPaperTilt{-10.8, 0.18, 121};
// D4's default measuring sector: 270 deg at 0.25 deg.
inline constexpr AngleGrid kFullSectorHead{-135.0, 0.25, 1081};

// Every stride-th ray, in order (a smaller but still representative batch).
[[nodiscard]] std::vector<raycast::Ray> every_nth(const std::vector<raycast::Ray>& rays, std::size_t stride);

}  // namespace ldoem::bench
