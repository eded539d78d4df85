// Hard cases the scanner meets in practice: two surfaces at the same place (the same answer
// from both casters: the lower object index wins a tie), rays tangent to spheres and cylinders,
// rays grazing mesh triangles, a mesh far from the origin, and rays from outside the box around
// all of Embree's geometry that only just reach it (Embree's caster skips the others).
#include "caster_fixture.hpp"

#include <cmath>

namespace ldoem::raycast {
namespace {

using namespace ldoem::raycast::testing;

template <class Caster>
class HardCaseTest : public ::testing::Test {};
TYPED_TEST_SUITE(HardCaseTest, CasterTypes);

// Two boxes whose faces towards the scanner lie in the same plane x = 3, overlapping in y.
TYPED_TEST(HardCaseTest, CoincidentFaces_LowerObjectIndexWins) {
  for (const bool swapped : {false, true}) {
    std::vector<scene::SceneObject> objects{
        make_object(scene::Box{Eigen::Vector3d(1, 2, 2)}, Eigen::Vector3d(3.5, 0, 0), Eigen::Quaterniond::Identity(), 0.2),
        make_object(scene::Box{Eigen::Vector3d(2, 1, 1)}, Eigen::Vector3d(4.0, 0, 0), Eigen::Quaterniond::Identity(), 0.9),
    };
    if (swapped) std::swap(objects[0], objects[1]);
    auto rig = rig_of<TypeParam>(std::move(objects));
    for (const double y : {-0.3, 0.0, 0.21, 0.4}) {
      const auto hit = rig->caster.cast(make_ray({0, y, 0.1}, {1, 0, 0}, 10));
      ASSERT_TRUE(hit.has_value()) << y;
      EXPECT_NEAR(hit->range_m, 3.0, 1e-9) << y;
      EXPECT_EQ(hit->object_index, 0u) << "swapped " << swapped << ", y " << y;
    }
  }
}

// Two coincident spheres: the same surface everywhere.
TYPED_TEST(HardCaseTest, CoincidentSpheres_LowerObjectIndexWins) {
  auto rig = rig_of<TypeParam>({
      make_object(scene::Sphere{0.5}, Eigen::Vector3d(5, 0, 0), Eigen::Quaterniond::Identity(), 0.3),
      make_object(scene::Sphere{0.5}, Eigen::Vector3d(5, 0, 0), Eigen::Quaterniond::Identity(), 0.7),
  });
  for (int i = -4; i <= 4; ++i) {
    const auto hit = rig->caster.cast(make_ray({0, 0, 0}, {5, 0.1 * i, 0.05 * i}, 20));
    ASSERT_TRUE(hit.has_value()) << i;
    EXPECT_EQ(hit->object_index, 0u) << i;
  }
}

// Rays passing a sphere of radius 1 at distance 1 - d from its centre: hit while d > 0 (at the
// closed-form range), nothing beyond the tangent, never NaN.
TYPED_TEST(HardCaseTest, TangentRaysOnASphere_HitUpToTheTangentNothingBeyond) {
  auto rig = rig_of<TypeParam>({make_object(scene::Sphere{1.0}, Eigen::Vector3d(5, 0, 0))});
  for (const double d : {1e-1, 1e-3, 1e-6, 1e-9}) {
    const Ray inside = make_ray({0, 1.0 - d, 0}, {1, 0, 0}, 20);
    const auto hit = rig->caster.cast(inside);
    expect_sane(hit, inside);
    ASSERT_TRUE(hit.has_value()) << d;
    const double half_chord = std::sqrt(1.0 - (1.0 - d) * (1.0 - d));
    EXPECT_NEAR(hit->range_m, 5.0 - half_chord, 1e-7) << d;
    const Ray outside = make_ray({0, 1.0 + d, 0}, {1, 0, 0}, 20);
    const auto miss = rig->caster.cast(outside);
    expect_sane(miss, outside);
    EXPECT_FALSE(miss.has_value()) << d;
  }
}

// The same beside a standing cylinder of radius 0.0975 (the corridor's), through its side.
TYPED_TEST(HardCaseTest, TangentRaysOnACylinder_HitUpToTheTangentNothingBeyond) {
  constexpr double kRadius = 0.0975;
  auto rig = rig_of<TypeParam>({make_object(scene::Cylinder{kRadius, 1.0}, Eigen::Vector3d(2.9, 0, 0.5))});
  for (const double d : {1e-3, 1e-6, 1e-9}) {
    const Ray inside = make_ray({0, kRadius - d, 0.5}, {1, 0, 0}, 20);
    const auto hit = rig->caster.cast(inside);
    expect_sane(hit, inside);
    ASSERT_TRUE(hit.has_value()) << d;
    const double half_chord = std::sqrt(kRadius * kRadius - (kRadius - d) * (kRadius - d));
    EXPECT_NEAR(hit->range_m, 2.9 - half_chord, 1e-7) << d;
    const Ray outside = make_ray({0, kRadius + d, 0.5}, {1, 0, 0}, 20);
    const auto miss = rig->caster.cast(outside);
    expect_sane(miss, outside);
    EXPECT_FALSE(miss.has_value()) << d;
  }
}

// A 2 km square floor mesh, rays from 0.5 m above it down to 1e-6 rad below the horizon: a
// finite hit at 0.5 / sin(e) within max range. Embree answers triangle hits in double from the
// triangle's plane, except very close to grazing, where its float distance (1e-7 relative) is
// kept (docs/scenes.md).
TEST(EmbreeMeshGrazing, FloorMesh_FiniteHitAtTheRightRange) {
  scene::Mesh floor;
  floor.vertices_m = {{-1000, -1000, 0}, {1000, -1000, 0}, {1000, 1000, 0}, {-1000, 1000, 0}};
  floor.triangles = {{0, 1, 2}, {0, 2, 3}};
  auto rig = rig_of<EmbreeRayCaster>({make_object(floor, Eigen::Vector3d::Zero())});
  for (const double elevation_rad : {1e-3, 1e-2, 0.1, 0.5, 1.5}) {
    const Ray ray = make_ray({0, 0, 0.5}, Eigen::Vector3d(std::cos(elevation_rad), 0, -std::sin(elevation_rad)), 999);
    const auto hit = rig->caster.cast(ray);
    expect_sane(hit, ray);
    ASSERT_TRUE(hit.has_value()) << elevation_rad;
    const double expected_m = 0.5 / std::sin(elevation_rad);
    EXPECT_NEAR(hit->range_m, expected_m, 1e-6 * expected_m) << elevation_rad;
  }
  // Parallel to the mesh, or along it: nothing, and never NaN.
  for (const double z : {0.5, 0.0}) {
    const Ray ray = make_ray({0, 0, z}, {1, 0, 0}, 999);
    const auto hit = rig->caster.cast(ray);
    expect_sane(hit, ray);
  }
}

// A mesh placed 1e5 m from the origin by its pose: its vertices stay small floats in the
// object's frame, the caster re-centres them in double, so the range is exact to 1e-9 m (a float
// world coordinate at 1e5 m would be 7.8 mm coarse).
TEST(EmbreeMeshFarAway, QuadAt1e5Metres_RangeExactToANanometre) {
  scene::Mesh quad;
  quad.vertices_m = {{0, -1, -1}, {0, 1, -1}, {0, 1, 1}, {0, -1, 1}};
  quad.triangles = {{0, 2, 1}, {0, 3, 2}};
  const Eigen::Vector3d far(1e5, -2e5, 3e4);
  auto rig = rig_of<EmbreeRayCaster>({make_object(quad, far)});
  for (const double offset : {0.0, 0.123456, 0.987654}) {
    const Eigen::Vector3d origin = far + Eigen::Vector3d(-5.0 - offset, 0.3, -0.2);
    const auto hit = rig->caster.cast(make_ray(origin, {1, 0, 0}, 20));
    ASSERT_TRUE(hit.has_value()) << offset;
    EXPECT_NEAR(hit->range_m, 5.0 + offset, 1e-9) << offset;
  }
}

// EmbreeRayCaster skips a ray whose reach misses the box around its geometry. From outside
// that box, rays along its faces and edges, and rays whose reach ends at, just before or just
// past the surface, must get ODE's answer: a skip that is not conservative would drop a hit.
TEST(EmbreeSkip, RaysThatOnlyJustReachTheGeometry_SameAnswerAsOde) {
  scene::Scene s;
  // A unit box at (5, 0, 0.5) is the whole box around Embree's geometry (the plane is not in it).
  s.objects = {make_object(scene::Plane{Eigen::Vector3d::UnitZ(), 0.0}, Eigen::Vector3d::Zero()),
               make_object(scene::Box{Eigen::Vector3d::Ones()}, Eigen::Vector3d(5, 0, 0.5))};
  const OdeWorld world(s);
  const EmbreeRayCaster embree(world);
  const OdeRayCaster ode(world);
  std::vector<Ray> rays;
  for (int k = -3; k <= 3; ++k) {
    const double offset_m = k * 1e-12;
    for (const double z : {1.0 + offset_m, 0.5, 1e-3}) {
      rays.push_back(make_ray({0, 0.5 + offset_m, z}, {1, 0, 0}, 10));   // along the face y = 0.5
      rays.push_back(make_ray({0, -0.5 - offset_m, z}, {1, 0, 0}, 10));  // along the face y = -0.5
    }
    // Reach ending at the near face x = 4.5, or that far plus or minus a little.
    for (const double reach_m : {4.5, 4.5 + offset_m, 4.5 - 1e-9, std::nextafter(4.5, 0.0)}) {
      rays.push_back(make_ray({0, 0.1, 0.5}, {1, 0, 0}, reach_m));
    }
    // Diagonal rays through the box's edge at x = 4.5, y = 0.5 and its corner (4.5, 0.5, 1).
    rays.push_back(make_ray(Eigen::Vector3d(4.5, 0.5, 0.5) + Eigen::Vector3d(-3, 3, 0) + offset_m * Eigen::Vector3d::UnitY(),
                            {1, -1, 0}, 20));
    rays.push_back(make_ray(Eigen::Vector3d(4.5, 0.5, 1.0) + Eigen::Vector3d(-2, 2, 2) + offset_m * Eigen::Vector3d::UnitZ(),
                            {1, -1, -1}, 20));
  }
  // From far away: the margin grows with the distance, the answer must not change.
  rays.push_back(make_ray({-1e6, 0.5, 0.5}, {1, 0, 0}, 2e6));
  rays.push_back(make_ray({5, 0.5, 1e5}, {0, 0, -1}, 2e5));
  int hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto expected = ode.cast(rays[i]);
    const auto got = embree.cast(rays[i]);
    ASSERT_EQ(got.has_value(), expected.has_value()) << "ray " << i;
    if (!expected) continue;
    ++hits;
    EXPECT_EQ(got->object_index, expected->object_index) << "ray " << i;
    EXPECT_NEAR(got->range_m, expected->range_m, 1e-9) << "ray " << i;
  }
  EXPECT_GT(hits, static_cast<int>(rays.size()) / 2);  // the rays do reach the box, mostly
}

}  // namespace
}  // namespace ldoem::raycast
