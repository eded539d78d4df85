// The baseline the fast caster is held against: a plain Embree 3 scene of triangles (default
// build quality, no robust flag), every object tessellated (tessellate.hpp), float rays, the hit
// distance taken as Embree reports it. This is what a simulator that gives up exact primitives
// would run; ldoem's EmbreeRayCaster must stay within a fixed share of it (docs/performance.md).
#pragma once

#include "tessellate.hpp"

#include <ldoem/raycast/ray_caster.hpp>
#include <ldoem/scene/scene.hpp>

#include <memory>

namespace ldoem::bench {

class EmbreeTriangleCaster final : public raycast::RayCaster {
 public:
  EmbreeTriangleCaster(const scene::Scene& scene, TriangleSoup soup);
  ~EmbreeTriangleCaster() override;
  EmbreeTriangleCaster(const EmbreeTriangleCaster&) = delete;
  EmbreeTriangleCaster& operator=(const EmbreeTriangleCaster&) = delete;

  std::optional<raycast::Hit> cast(const raycast::Ray& ray) const override;
  [[nodiscard]] std::size_t triangle_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ldoem::bench
