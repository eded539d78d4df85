// The beam's footprint as sub-rays (mixed_pixels' hexagonal pattern), shared by the stages that
// cast it: mixed_pixels and waveform.
#pragma once

#include <ldoem/raycast/ray_caster.hpp>

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <optional>
#include <span>

namespace ldoem::sensor::detail {

inline constexpr std::size_t kMaxSubrays = 37;  // three hexagonal rings

struct FootprintCast {
  std::array<raycast::Ray, kMaxSubrays> rays;
  std::array<std::optional<raycast::Hit>, kMaxSubrays> hits;
  std::size_t count = 0;
  [[nodiscard]] std::span<const raycast::Ray> ray_span() const { return {rays.data(), count}; }
  [[nodiscard]] std::span<const std::optional<raycast::Hit>> hit_span() const { return {hits.data(), count}; }
};

// Two unit vectors perpendicular to the direction and to each other, chosen deterministically
// (only their plane matters for a rotationally symmetric beam).
inline std::array<Eigen::Vector3d, 2> perpendicular_basis(const Eigen::Vector3d& direction) {
  const Eigen::Vector3d helper =
      std::abs(direction.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d first = helper.cross(direction).normalized();
  return {first, direction.cross(first)};
}

// Casts one sub-ray per offset (at most kMaxSubrays) around `central`, one RayCaster::cast each.
inline void cast_footprint(const raycast::Ray& central, std::span<const Eigen::Vector2d> offsets,
                           const raycast::RayCaster& caster, FootprintCast& out) {
  out.count = std::min(offsets.size(), kMaxSubrays);
  const auto [across, up] = perpendicular_basis(central.direction);
  for (std::size_t i = 0; i < out.count; ++i) {
    const Eigen::Vector2d& offset = offsets[i];
    out.rays[i] = central;
    out.rays[i].direction =
        (central.direction + std::tan(offset.x()) * across + std::tan(offset.y()) * up).normalized();
  }
  for (std::size_t i = 0; i < out.count; ++i) out.hits[i] = caster.cast(out.rays[i]);
}

}  // namespace ldoem::sensor::detail
