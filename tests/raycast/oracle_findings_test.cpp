// Disagreements the exact oracle's differential fuzzer found (docs/numerics.md "Findings"),
// each reduced to the smallest scene that shows it, with the answer the oracle gives.
#include "caster_fixture.hpp"

#include "ldoem/raycast/moving_ray_caster.hpp"

#include <cstdlib>

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

// Found: spheres of 1e-6 m seen from 800 m. Embree traversed a float copy of the ray whose
// rounding (~6e-8 of 800 m, 5e-5 m sideways) exceeded the padding of the boxes (1e-5 of the
// scene's size, a scene of 1e-6 m), so the sphere was never tested and the caster missed it.
TEST(OracleFindings, TinySphereFromFarAway_IsHit) {
  const Eigen::Vector3d centre(-1.7446140151343865, -2.160481332999503, -22.075968050757773);
  // Two of them 1e-11 m apart (with one, Embree's tree is a single leaf and tests no box).
  auto rig = rig_of<EmbreeRayCaster>({make_object(scene::Sphere{1.07e-6}, centre),
                                      make_object(scene::Sphere{1.07e-6}, centre + Eigen::Vector3d(-4e-12, 1.6e-11, -9e-12))});
  for (int i = 0; i < 64; ++i) {  // directions all round
    const double phi = 0.1 + 0.37 * i, z = -0.9 + 1.8 * i / 63.0;
    const Eigen::Vector3d unit(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
    const Eigen::Vector3d beside = 1e-7 * unit.unitOrthogonal();  // 1e-7 m off the centre
    const Ray ray = make_ray(centre + beside - 800.0 * unit, unit, 5000.0);
    const auto hit = rig->caster.cast(ray);
    expect_sane(hit, ray);
    ASSERT_TRUE(hit.has_value()) << unit.transpose();
    EXPECT_NEAR(hit->range_m, 800.0 - std::sqrt(1.07e-6 * 1.07e-6 - 1e-14), 1e-10) << unit.transpose();
  }
}

// Every object where the scene put it, for ever.
class FixedPoses final : public MotionSource {
 public:
  explicit FixedPoses(std::vector<scene::Pose> poses) : poses_(std::move(poses)) {}
  scene::Pose pose_at(std::size_t k, double) const override { return poses_[k]; }
  scene::PathBounds origin_bounds(std::size_t k, double, double) const override { return {poses_[k].position_m, poses_[k].position_m}; }
  bool keeps_orientation(std::size_t) const override { return true; }

 private:
  std::vector<scene::Pose> poses_;
};

// A closed unit cube as 12 triangles about its centre.
scene::Mesh closed_cube_mesh() {
  scene::Mesh mesh;
  mesh.path = "inline";
  for (int i = 0; i < 8; ++i) mesh.vertices_m.emplace_back(i & 1 ? 0.5f : -0.5f, i & 2 ? 0.5f : -0.5f, i & 4 ? 0.5f : -0.5f);
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

// Found (scenes/hard/mesh_edges.yaml's seed): a ray leaving a moving mesh's face from a point
// on it. ODE's trimesh reported only its closest triangle, the face the ray starts on (range 0,
// no hit), and the moving caster answered nothing instead of the face the ray leaves through.
TEST(OracleFindings, MovingMesh_RayFromItsFaceFindsTheExit) {
  std::vector<scene::SceneObject> objects{make_object(closed_cube_mesh(), Eigen::Vector3d(0, 4, 0))};
  const FixedPoses still({objects[0].pose});
  MovingRayCaster caster(objects, {0}, still);
  caster.prepare(0.0, 1.0);
  for (const Eigen::Vector3d& direction : {Eigen::Vector3d(0.3, 0.2, 1), Eigen::Vector3d(-0.1, 0.4, 1), Eigen::Vector3d(0, 0, 1)}) {
    const Ray ray = make_ray(Eigen::Vector3d(0.1, 4.05, -0.5), direction, 10);
    const auto hit = caster.cast(ray);
    expect_sane(hit, ray);
    ASSERT_TRUE(hit.has_value()) << direction.transpose();
    EXPECT_EQ(hit->object_index, 0u);
    // It leaves through the top face z = 0.5 (the side faces are farther for these directions).
    EXPECT_NEAR(hit->range_m, 1.0 / ray.direction.z(), 1e-6) << direction.transpose();
  }
}

// Found: the moving caster had the same fault as TinySphereFromFarAway_IsHit with its swept
// boxes: a sphere of 1e-6 m 800 m away was never tested.
TEST(OracleFindings, MovingTinySphereFromFarAway_IsHit) {
  const Eigen::Vector3d centre(-1.7446140151343865, -2.160481332999503, -22.075968050757773);
  std::vector<scene::SceneObject> objects{make_object(scene::Sphere{1.07e-6}, centre),
                                         make_object(scene::Sphere{1.07e-6}, centre + Eigen::Vector3d(-4e-12, 1.6e-11, -9e-12))};
  const FixedPoses still({objects[0].pose, objects[1].pose});
  MovingRayCaster caster(objects, {0, 1}, still);
  caster.prepare(0.0, 1.0);
  for (int i = 0; i < 64; ++i) {
    const double phi = 0.1 + 0.37 * i, z = -0.9 + 1.8 * i / 63.0;
    const Eigen::Vector3d unit(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
    const Ray ray = make_ray(centre + 1e-7 * unit.unitOrthogonal() - 800.0 * unit, unit, 5000.0);
    const auto hit = caster.cast(ray);
    expect_sane(hit, ray);
    ASSERT_TRUE(hit.has_value()) << unit.transpose();
    EXPECT_NEAR(hit->range_m, 800.0 - std::sqrt(1.07e-6 * 1.07e-6 - 1e-14), 1e-10) << unit.transpose();
  }
}

// Found: the moving caster answered meshes through ODE's trimesh (OPCODE), in float in the
// object's frame: ranges off by up to 1e-4 of themselves (2757.20 m for an exact 2757.36 m),
// hits on triangles the ray misses by more than the float edge tolerance. Now a moving mesh is
// answered as the static caster answers one (mesh_index.cpp): both agree with the range from
// the triangle's double plane to within the double bound of docs/numerics.md.
TEST(OracleFindings, MovingMesh_RangeFromTheDoublePlane) {
  scene::SceneObject slab = make_object(triangle_mesh({{-60, -50, 3}, {70, -40, -5}, {-5, 65, 1}}), Eigen::Vector3d(1500, 2100, 40));
  slab.pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()));
  const FixedPoses still({slab.pose});
  MovingRayCaster moving({slab}, {0}, still);
  moving.prepare(0.0, 1.0);
  auto rig = rig_of<EmbreeRayCaster>({slab});
  const scene::Mesh& mesh = std::get<scene::Mesh>(slab.shape);
  std::vector<Eigen::Vector3d> world;
  for (const Eigen::Vector3f& v : mesh.vertices_m) world.push_back(slab.pose.position_m + slab.pose.orientation * v.cast<double>());
  const Eigen::Vector3d normal = (world[1] - world[0]).cross(world[2] - world[0]).normalized();
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d origin(0.37 * i, -0.11 * i, 1.3);
    // Aimed at points spread over the triangle (barycentric), each a little inside its edges.
    const double a = 0.05 + 0.9 * ((i * 37) % 101) / 101.0, b = (1.0 - a) * (0.05 + 0.9 * ((i * 53) % 97) / 97.0);
    const Eigen::Vector3d target = world[0] + a * (world[1] - world[0]) + b * (world[2] - world[0]);
    const Ray ray = make_ray(origin, target - origin, 1e4);
    const double expected = normal.dot(world[0] - ray.origin_m) / normal.dot(ray.direction.normalized());
    for (const auto& hit : {moving.cast(ray), rig->caster.cast(ray)}) {
      expect_sane(hit, ray);
      ASSERT_TRUE(hit.has_value()) << i;
      EXPECT_NEAR(hit->range_m, expected, 1e-9) << i;
    }
    ++hits;
  }
  EXPECT_EQ(hits, 400);
}

// Found (sweep, docs/numerics.md "Findings" 7): a mesh of two crossing 500 m triangles 1.4e6 m
// from the origin, a ray meeting one at 73.24 m (cos 0.17) and grazing the other's plane
// (cos 1.1e-6) at 79.63 m. Embree's float distance to the grazing triangle (its error grows as
// 1/cos) came out nearer than the other's; the mesh query took it, Embree cut the ray off at
// that float distance, and the caster answered the grazing triangle's (correct) double range,
// 79.63 m, past the nearer triangle. Now the query's filter keeps the nearest *double* range
// and sets Embree's tfar from it, so a triangle is cut off only by another's double range.
TEST(OracleFindings, MovingMesh_GrazingTriangleDoesNotHideANearerOne) {
  const auto hex = [](const char* x) { return std::strtod(x, nullptr); };
  const auto hexf = [&](const char* x, const char* y, const char* z) {
    return Eigen::Vector3f(static_cast<float>(hex(x)), static_cast<float>(hex(y)), static_cast<float>(hex(z)));
  };
  scene::SceneObject mesh = make_object(triangle_mesh({hexf("0x1.7b4958p+8", "-0x1.9964a4p+4", "-0x1.8bb39p+8"),
                                                       hexf("-0x1.791c8ap+8", "0x1.258a56p+8", "0x1.e77318p+7"),
                                                       hexf("-0x1.c16e3cp+6", "-0x1.cd1eb8p+7", "0x1.8fb0ep+7"),
                                                       hexf("-0x1.2a3ef4p+6", "-0x1.46cda8p+6", "-0x1.9f24c6p+8"),
                                                       hexf("-0x1.3310c6p+7", "-0x1.41732p+8", "0x1.4e67eap+6"),
                                                       hexf("-0x1.3505fp+7", "0x1.021da2p+8", "0x1.5e639ap+6")}),
                                        Eigen::Vector3d(hex("0x1.e8995d7abe7a8p+19"), hex("-0x1.e85f9069d4f25p+19"),
                                                        hex("0x1.24f6bea061b25p+18")));
  mesh.pose.orientation = Eigen::Quaterniond(hex("0x1.6a09e667f3bcdp-1"), 0.0, 0.0, hex("0x1.6a09e667f3bccp-1"));
  const FixedPoses still({mesh.pose});
  MovingRayCaster moving({mesh}, {0}, still);
  moving.prepare(0.0, 1.0);
  // The case's ray exactly (make_ray would normalise the direction again).
  const Ray ray{Eigen::Vector3d(hex("0x1.e88d9bf35e8abp+19"), hex("-0x1.e871509e6e2f3p+19"), hex("0x1.250cede823ec8p+18")),
                Eigen::Vector3d(hex("-0x1.e6a45bc06fedp-1"), hex("-0x1.0514ab210c13dp-3"), hex("-0x1.2243a9e27a0d4p-2")),
                hex("0x1.5a4ce4d4dfad4p+15"), 0.0};
  const auto hit = moving.cast(ray);
  expect_sane(hit, ray);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->object_index, 0u);
  // The oracle's exact range of the nearer triangle: 73.240778630656649 m (bound 0.0039 m).
  EXPECT_NEAR(hit->range_m, 73.240778630656649, 1e-6);
}

// Found (a --far-meshes sweep, docs/numerics.md "Findings" 8): a sliver triangle (edges 1.06e-7
// rad apart, 8.5 m long) posed 1.4e6 m out, a ray starting 5e-10 m from it and grazing its plane
// (cos 5.5e-6). The exact plane crossing is behind the origin (no hit); the plain double cross
// product turned the sliver's normal by ~1e-9 rad, which put the crossing 1.08e-4 m ahead, and
// the caster answered that. The normal is now taken to within an ulp per component.
TEST(OracleFindings, MovingSliver_NormalFromAnAccurateCrossProduct) {
  const auto hex = [](const char* x) { return std::strtod(x, nullptr); };
  const auto hexf = [&](const char* x, const char* y, const char* z) {
    return Eigen::Vector3f(static_cast<float>(hex(x)), static_cast<float>(hex(y)), static_cast<float>(hex(z)));
  };
  scene::SceneObject sliver = make_object(triangle_mesh({hexf("-0x1.4b6bdep-1", "-0x1.c02068p+1", "-0x1.5a9522p+2"),
                                                         hexf("-0x1.404f5p+2", "0x1.2cc37cp+1", "-0x1.1eff86p+0"),
                                                         hexf("-0x1.948a06p+1", "-0x1.0368e2p-3", "-0x1.7826dep+1")}),
                                          Eigen::Vector3d(hex("0x1.e848d42e854cfp+19"), hex("-0x1.e8473545bb46p+19"),
                                                          hex("0x1.24fa492cb9d66p+18")));
  sliver.pose.orientation = Eigen::Quaterniond(hex("-0x1.e4de1e91bea07p-2"), hex("-0x1.4108174d44388p-1"),
                                               hex("-0x1.081bb389c17ap-1"), hex("0x1.5d9a215a88e82p-2"));
  const FixedPoses still({sliver.pose});
  MovingRayCaster moving({sliver}, {0}, still);
  moving.prepare(0.0, 1.0);
  const Ray ray{Eigen::Vector3d(hex("0x1.e848caeaa09e6p+19"), hex("-0x1.e847185613d24p+19"), hex("0x1.24fb642053c15p+18")),
                Eigen::Vector3d(hex("-0x1.f7eba446111eep-1"), hex("-0x1.0780ceb71ce4ap-4"), hex("0x1.5198ee308a7dbp-3")),
                hex("0x1.1188faf151ea2p+9"), 0.0};
  const auto hit = moving.cast(ray);
  expect_sane(hit, ray);
  EXPECT_FALSE(hit.has_value()) << hit->range_m;
}


// Found (docs/numerics.md "Findings" 12, far-mesh sweep case 069f2bab...): the same sliver
// through the static caster, whose planes (built once) took the plain cross product before. A
// single triangle 10.8 m long and 5e-6 m wide (twice its area 2.7e-5 m^2) posed 1e6 m out; the
// ray passes 5e-10 m from its plane at cos 1.8e-6. Embree's float test takes the triangle (its
// crossing is decided only to metres along so grazing a plane), and the plain normal put the
// double crossing 3.0e-4 m ahead; the exact one is 4.0e-5 m behind the origin: no hit.
TEST(OracleFindings, StaticSliver_NormalFromAnAccurateCrossProduct) {
  const auto hex = [](const char* x) { return std::strtod(x, nullptr); };
  const auto hexf = [&](const char* x, const char* y, const char* z) {
    return Eigen::Vector3f(static_cast<float>(hex(x)), static_cast<float>(hex(y)), static_cast<float>(hex(z)));
  };
  scene::SceneObject sliver = make_object(triangle_mesh({hexf("0x1.217636p+2", "-0x1.88287ep+1", "-0x1.4713ep+1"),
                                                         hexf("-0x1.2489a2p+2", "-0x1.489e3ap+1", "0x1.9d0f7ap+1"),
                                                         hexf("-0x1.14958ep+2", "-0x1.4a5c22p+1", "0x1.88c598p+1")}),
                                          Eigen::Vector3d(hex("0x1.e847d3a5fab0cp+19"), hex("-0x1.e847772d5f8cbp+19"),
                                                          hex("0x1.24fab504e7135p+18")));
  sliver.pose.orientation = Eigen::Quaterniond(hex("-0x1.55da3a12a38cdp-1"), hex("0x1.f80e4dad43213p-3"),
                                               hex("-0x1.9df503324a513p-2"), hex("0x1.263684b202a1cp-1"));
  // The case's other objects, which the ray misses: with them Embree's float frame (the centre
  // of every bound) and so the float triangle are the case's.
  const Eigen::Vector3d axis(hex("0x1.e8479ed69739p+19"), hex("-0x1.e847cfd6aeadap+19"), hex("0x1.24f981447461fp+18"));
  const scene::Cylinder cylinder{hex("0x1.61b24f9fc6f59p-1"), hex("0x1.61b24f9fc6f59p+0")};
  auto rig = rig_of<EmbreeRayCaster>(
      {make_object(cylinder, axis), sliver, make_object(cylinder, Eigen::Vector3d(hex("0x1.e8479ed697391p+19"), axis.y(), axis.z())),
       make_object(scene::Box{Eigen::Vector3d(hex("0x1.ba11b1e81d28ap+3"), hex("0x1.96677716ce677p+2"), hex("0x1.a2182d94b752bp+3"))},
                   Eigen::Vector3d(hex("0x1.e846ed75d5249p+19"), hex("-0x1.e846717c07ddfp+19"), hex("0x1.24fa66e53c163p+18")))});
  const Ray ray{Eigen::Vector3d(hex("0x1.e847ab1eb30b4p+19"), hex("-0x1.e8478888dd73fp+19"), hex("0x1.24fb541259981p+18")),
                Eigen::Vector3d(hex("-0x1.3c3ddaac725d9p-1"), hex("-0x1.3cee56a7a3a74p-1"), hex("-0x1.f0bfd412450e3p-2")),
                hex("0x1.5ac9d411a812cp+9"), 0.0};
  const auto hit = rig->caster.cast(ray);
  expect_sane(hit, ray);
  EXPECT_FALSE(hit.has_value()) << hit->range_m;
}

}  // namespace
}  // namespace ldoem::raycast
