// Disagreements the exact oracle's differential fuzzer found (docs/numerics.md "Findings"),
// each reduced to the smallest scene that shows it, with the answer the oracle gives.
#include "caster_fixture.hpp"

namespace ldoem::raycast {
namespace {

using namespace ldoem::raycast::testing;

scene::Mesh triangle_mesh(std::vector<Eigen::Vector3f> vertices) {
  scene::Mesh mesh;
  mesh.path = "inline";
  mesh.vertices_m = std::move(vertices);
  for (std::uint32_t i = 0; i + 2 < mesh.vertices_m.size(); i += 3) mesh.triangles.push_back({i, i + 1, i + 2});
  return mesh;
}

// Found: a ray leaving a mesh triangle's surface (range 0, which is no hit) made Embree accept
// the triangle at t = 0; its tfar of 0 then hid everything else, and the caster answered
// nothing (or a farther plane) instead of the sphere the origin is inside.
TEST(OracleFindings, OriginOnATriangle_DoesNotHideTheSphereAround) {
  auto rig = rig_of<EmbreeRayCaster>({
      make_object(triangle_mesh({{0, -0.5f, -0.5f}, {0, 0.5f, -0.5f}, {0, 0, 0.5f}}), Eigen::Vector3d::Zero()),
      make_object(scene::Sphere{1.0}, Eigen::Vector3d::Zero()),
      make_object(scene::Plane{Eigen::Vector3d::UnitX(), 5.0}, Eigen::Vector3d::Zero()),
  });
  for (const Eigen::Vector3d& direction : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0.2, 0.1), Eigen::Vector3d(1, -0.3, 0.3)}) {
    const Ray ray = make_ray(Eigen::Vector3d::Zero(), direction, 10);
    const auto hit = rig->caster.cast(ray);
    expect_sane(hit, ray);
    ASSERT_TRUE(hit.has_value()) << direction.transpose();
    EXPECT_EQ(hit->object_index, 1u) << direction.transpose();
    EXPECT_NEAR(hit->range_m, 1.0, 1e-15) << direction.transpose();
  }
}

}  // namespace
}  // namespace ldoem::raycast
