// docs/scenes.md "Numerical edge cases": one test per case, for both casters. Never NaN, never
// Inf, never a crash; the documented result where one is promised.
#include "caster_fixture.hpp"

#include <limits>
#include <numbers>

namespace ldoem::raycast {
namespace {

using namespace ldoem::raycast::testing;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

template <class Caster>
class EdgeCaseTest : public ::testing::Test {};
TYPED_TEST_SUITE(EdgeCaseTest, CasterTypes);

scene::SceneObject floor_plane() {
  return make_object(scene::Plane{Eigen::Vector3d::UnitZ(), 0.0}, Eigen::Vector3d::Zero());
}

TYPED_TEST(EdgeCaseTest, GrazingPlane_FiniteHitOrNothingUpTo90Degrees) {
  auto rig = rig_of<TypeParam>({floor_plane()});
  const Eigen::Vector3d origin(0, 0, 0.5);
  // Elevation below the horizon: 90 deg incidence at 0, then ever steeper.
  for (double elevation_rad : {0.0, 1e-300, 1e-20, 1e-12, 1e-9, 1e-6, 1e-3, 0.01, 0.1, 0.5, 1.5}) {
    const Ray ray = make_ray(origin, Eigen::Vector3d(std::cos(elevation_rad), 0, -std::sin(elevation_rad)), 1e6);
    const auto hit = rig->caster.cast(ray);
    expect_sane(hit, ray);
    const double expected_m = 0.5 / std::sin(elevation_rad);
    if (expected_m <= ray.max_range_m) {
      ASSERT_TRUE(hit.has_value()) << elevation_rad;
      EXPECT_NEAR(hit->range_m, expected_m, 1e-9 * expected_m) << elevation_rad;
    } else {
      EXPECT_FALSE(hit.has_value()) << elevation_rad;  // parallel or beyond max range
    }
  }
}

TYPED_TEST(EdgeCaseTest, RayLyingInPlane_NoHit) {
  auto rig = rig_of<TypeParam>({floor_plane()});
  const Ray ray = make_ray(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d::UnitX(), 100);
  EXPECT_FALSE(rig->caster.cast(ray).has_value());
}

TYPED_TEST(EdgeCaseTest, BoxEdgeAndCorner_HitExactlyNoGap) {
  // Unit box at the origin; rays travel diagonally in the xy plane through the edge x=y=0.5.
  auto rig = rig_of<TypeParam>({make_object(scene::Box{Eigen::Vector3d::Ones()}, Eigen::Vector3d::Zero())});
  const Eigen::Vector3d direction = Eigen::Vector3d(-1, -1, 0).normalized();
  for (int k = -20; k <= 20; ++k) {
    const double offset_m = k * 1e-12;  // across the edge, perpendicular to the ray
    const Eigen::Vector3d origin = Eigen::Vector3d(2.5, 2.5, 0) + offset_m * Eigen::Vector3d(1, -1, 0).normalized();
    const Ray ray = make_ray(origin, direction, 10);
    const auto hit = rig->caster.cast(ray);
    expect_sane(hit, ray);
    ASSERT_TRUE(hit.has_value()) << k;
    EXPECT_NEAR(hit->range_m, 2.0 * std::numbers::sqrt2, 1e-9) << k;
  }
  // Exactly through the corner (0.5, 0.5, 0.5) along the main diagonal, and grazing along a face.
  const Ray corner = make_ray(Eigen::Vector3d(2, 2, 2), Eigen::Vector3d(-1, -1, -1), 10);
  const auto corner_hit = rig->caster.cast(corner);
  expect_sane(corner_hit, corner);
  ASSERT_TRUE(corner_hit.has_value());
  EXPECT_NEAR(corner_hit->range_m, 1.5 * std::sqrt(3.0), 1e-9);
  const Ray along_face = make_ray(Eigen::Vector3d(-2, 0, 0.5), Eigen::Vector3d::UnitX(), 10);
  expect_sane(rig->caster.cast(along_face), along_face);  // hit or not, but sane
}

TYPED_TEST(EdgeCaseTest, RayStartingInside_ReportsExitSurface) {
  auto rig = rig_of<TypeParam>({
      make_object(scene::Sphere{1.0}, Eigen::Vector3d(0, 0, 0)),
      make_object(scene::Box{Eigen::Vector3d(2, 4, 6)}, Eigen::Vector3d(10, 0, 0)),
      make_object(scene::Cylinder{0.5, 3.0}, Eigen::Vector3d(20, 0, 0)),
      make_object(scene::Capsule{0.5, 2.0}, Eigen::Vector3d(30, 0, 0)),
  });
  struct Case { Eigen::Vector3d origin, direction; double exit_m; std::uint32_t object; };
  const Case cases[] = {
      {{0, 0, 0}, {0, 1, 0}, 1.0, 0},    {{0.5, 0, 0}, {1, 0, 0}, 0.5, 0},
      {{10, 0, 0}, {0, 1, 0}, 2.0, 1},   {{10, 0, 0}, {0, 0, -1}, 3.0, 1},
      {{20, 0, 0}, {0, 1, 0}, 0.5, 2},   {{20, 0, 0}, {0, 0, 1}, 1.5, 2},
      {{30, 0, 0}, {0, -1, 0}, 0.5, 3},  {{30, 0, 0}, {0, 0, 1}, 1.5, 3},
  };
  for (const Case& c : cases) {
    const Ray ray = make_ray(c.origin, c.direction, 5.0);
    const auto hit = rig->caster.cast(ray);
    expect_sane(hit, ray);
    ASSERT_TRUE(hit.has_value()) << c.origin.transpose();
    EXPECT_EQ(hit->object_index, c.object);
    EXPECT_NEAR(hit->range_m, c.exit_m, 1e-9) << c.origin.transpose();
    EXPECT_NEAR(hit->normal.dot(ray.direction), -1.0, 1e-9);  // turned to face the ray
  }
}

TYPED_TEST(EdgeCaseTest, SceneFarFromOrigin_SameRangesAsAtOrigin) {
  const Eigen::Vector3d far(1e5, -1e5, 1e5);
  auto build = [](const Eigen::Vector3d& shift) {
    return rig_of<TypeParam>({
        make_object(scene::Box{Eigen::Vector3d(0.2, 10, 3)}, shift + Eigen::Vector3d(4.28, 0, 1.5)),
        make_object(scene::Cylinder{0.0975, 0.998}, shift + Eigen::Vector3d(2.9, 0, 0.499)),
        make_object(scene::Sphere{0.3}, shift + Eigen::Vector3d(3.5, -0.8, 0.6)),
    });
  };
  auto near_rig = build(Eigen::Vector3d::Zero());
  auto far_rig = build(far);
  int hits = 0;
  for (int i = -40; i <= 40; ++i) {
    for (int j = -10; j <= 10; ++j) {
      const Eigen::Vector3d direction(1.0, 0.01 * i, 0.01 * j);
      const Eigen::Vector3d origin(0, 0, 0.5);
      const auto expected = near_rig->caster.cast(make_ray(origin, direction, 30));
      const Ray shifted = make_ray(origin + far, direction, 30);
      const auto hit = far_rig->caster.cast(shifted);
      expect_sane(hit, shifted);
      ASSERT_EQ(expected.has_value(), hit.has_value()) << i << "," << j;
      if (!hit) continue;
      ++hits;
      EXPECT_EQ(hit->object_index, expected->object_index);
      EXPECT_NEAR(hit->range_m, expected->range_m, 1e-6 * expected->range_m) << i << "," << j;
    }
  }
  EXPECT_GT(hits, 1000);
}

TYPED_TEST(EdgeCaseTest, TinyAndHugeObjects_HitWhereTheyAre) {
  auto rig = rig_of<TypeParam>({
      make_object(scene::Sphere{5e-5}, Eigen::Vector3d(2, 0, 0)),
      make_object(scene::Box{Eigen::Vector3d::Constant(1e-4)}, Eigen::Vector3d(2, 1, 0)),
      make_object(scene::Box{Eigen::Vector3d::Constant(1e4)}, Eigen::Vector3d(5010, 0, 0)),
  });
  const auto sphere_hit = rig->caster.cast(make_ray({0, 0, 0}, {1, 0, 0}, 100));
  ASSERT_TRUE(sphere_hit.has_value());
  EXPECT_EQ(sphere_hit->object_index, 0u);
  EXPECT_NEAR(sphere_hit->range_m, 2.0 - 5e-5, 1e-12);
  const auto box_hit = rig->caster.cast(make_ray({0, 1, 0}, {1, 0, 0}, 100));
  ASSERT_TRUE(box_hit.has_value());
  EXPECT_EQ(box_hit->object_index, 1u);
  EXPECT_NEAR(box_hit->range_m, 2.0 - 5e-5, 1e-12);
  // 6e-5 m beside the tiny sphere: passes it and reaches the huge box at x = 10.
  const auto beside = rig->caster.cast(make_ray({0, 6e-5, 0}, {1, 0, 0}, 100));
  ASSERT_TRUE(beside.has_value());
  EXPECT_EQ(beside->object_index, 2u);
  EXPECT_NEAR(beside->range_m, 10.0, 1e-9);
  // From inside the huge box: its exit surface 9990 m away.
  const auto inside = rig->caster.cast(make_ray({5000, 0, 0}, {1, 0, 0}, 20000));
  ASSERT_TRUE(inside.has_value());
  EXPECT_NEAR(inside->range_m, 5010.0, 1e-9 * 5010.0);
}

TYPED_TEST(EdgeCaseTest, TinySphereFarAway_ExactAndNoAbort) {
  // Plain dCollide loses R^2 against the squared distance here (and may abort in ODE's
  // normalisation); the probe starts near the object instead.
  auto rig = rig_of<TypeParam>({make_object(scene::Sphere{1e-4}, Eigen::Vector3d(5000, 0, 0)),
                                make_object(scene::Sphere{1.0}, Eigen::Vector3d(0, 0, 9e8))});
  const auto hit = rig->caster.cast(make_ray({0, 0, 0}, {1, 0, 0}, 1e4));
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->range_m, 5000.0 - 1e-4, 1e-9);
  const auto grazing = rig->caster.cast(make_ray({0, 0, 0}, {0, 0, 1}, 1e9));
  ASSERT_TRUE(grazing.has_value());
  EXPECT_NEAR(grazing->range_m, 9e8 - 1.0, 1e-6);
  EXPECT_FALSE(rig->caster.cast(make_ray({0, 0, 0}, {1, 0, 0}, 4999)).has_value());
}

TYPED_TEST(EdgeCaseTest, InvalidRays_NoHitNoCrash) {
  auto rig = rig_of<TypeParam>({floor_plane(), make_object(scene::Sphere{1}, Eigen::Vector3d(3, 0, 1))});
  const Eigen::Vector3d o(0, 0, 1);
  const Ray invalid[] = {
      {o, Eigen::Vector3d::Zero(), 10},
      {o, Eigen::Vector3d(kNaN, 0, 0), 10},
      {o, Eigen::Vector3d(kInf, 0, 0), 10},
      {Eigen::Vector3d(kNaN, 0, 0), Eigen::Vector3d::UnitX(), 10},
      {Eigen::Vector3d(kInf, 0, 1), -Eigen::Vector3d::UnitX(), 10},
      {o, Eigen::Vector3d::UnitX(), 0.0},
      {o, Eigen::Vector3d::UnitX(), -1.0},
      {o, Eigen::Vector3d::UnitX(), kNaN},
      {o, Eigen::Vector3d::UnitX(), kInf},
      {o, Eigen::Vector3d(1e-200, 0, 0), 10},
      {Eigen::Vector3d(1e300, 0, 1), -Eigen::Vector3d::UnitX(), 1e308},  // beyond 1e9 m
  };
  for (const Ray& ray : invalid) EXPECT_FALSE(rig->caster.cast(ray).has_value());
  // Huge but finite numbers: anything sane.
  const Ray huge[] = {
      {Eigen::Vector3d(9e8, 0, 1), -Eigen::Vector3d::UnitX(), 1e308},
      {o, Eigen::Vector3d(1e300, 1e300, 0), 10},
      {o, Eigen::Vector3d::UnitX(), 1e308},
  };
  for (const Ray& ray : huge) {
    const auto hit = rig->caster.cast(ray);
    if (hit) {
      EXPECT_TRUE(std::isfinite(hit->range_m));
      EXPECT_TRUE(hit->normal.allFinite());
    }
  }
  // A non-unit direction is normalised: ranges stay in metres.
  const auto scaled = rig->caster.cast(Ray{o, Eigen::Vector3d(7, 0, 0), 10, 0.0});
  ASSERT_TRUE(scaled.has_value());
  EXPECT_NEAR(scaled->range_m, 2.0, 1e-12);
  // One within a few ulps of unit length is taken as it is (no square root per cast), one just
  // beyond that is normalised: both answer the unit ray's range to rounding.
  for (const double stretch : {1.0 + 2e-16, 1.0 - 2e-16, 1.0 + 1e-14, 1.0 - 1e-14, 1.0 + 1e-9}) {
    const auto hit = rig->caster.cast(Ray{o, stretch * Eigen::Vector3d(1, 0, 0), 10});
    ASSERT_TRUE(hit.has_value()) << stretch;
    EXPECT_NEAR(hit->range_m, 2.0, 1e-14) << stretch;
    EXPECT_NEAR(hit->normal.norm(), 1.0, 1e-15) << stretch;
  }
}

// Meshes: Embree's robust triangles do not leak across shared edges. (ODE's trimesh is not held
// to this: docs/scenes.md.)
scene::Mesh quad_mesh() {
  scene::Mesh mesh;
  mesh.vertices_m = {{0, -1, -1}, {0, 1, -1}, {0, 1, 1}, {0, -1, 1}};
  mesh.triangles = {{0, 2, 1}, {0, 3, 2}};  // shared diagonal (-1,-1) .. (1,1)
  return mesh;
}

scene::Mesh cube_mesh() {
  scene::Mesh mesh;
  for (int i = 0; i < 8; ++i) mesh.vertices_m.emplace_back((i & 1) - 0.5f, ((i >> 1) & 1) - 0.5f, ((i >> 2) & 1) - 0.5f);
  mesh.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return mesh;
}

TEST(EmbreeMeshEdges, GridAcrossSharedDiagonal_NoLeaks) {
  auto rig = rig_of<EmbreeRayCaster>({make_object(quad_mesh(), Eigen::Vector3d(3, 0, 0))});
  int rays = 0;
  for (int i = -50; i <= 50; ++i) {
    const double along = i * 0.019;
    for (int k = -30; k <= 30; ++k) {
      const double across = k * 1e-8;  // within float rounding of the diagonal
      const Ray ray = make_ray(Eigen::Vector3d(0, along + across, along - across), Eigen::Vector3d::UnitX(), 10);
      const auto hit = rig->caster.cast(ray);
      ASSERT_TRUE(hit.has_value()) << along << " " << across;
      EXPECT_NEAR(hit->range_m, 3.0, 1e-9);
      EXPECT_NEAR(hit->normal.x(), -1.0, 1e-12);
      ++rays;
    }
  }
  EXPECT_EQ(rays, 101 * 61);
}

TEST(EmbreeMeshEdges, ClosedCube_EdgesAndCornersNeverLeak) {
  auto rig = rig_of<EmbreeRayCaster>({make_object(cube_mesh(), Eigen::Vector3d(0, 0, 0))});
  // Rays from outside aimed at points on every edge and corner of the cube.
  for (int axis = 0; axis < 3; ++axis) {
    for (int corner = 0; corner < 8; ++corner) {
      Eigen::Vector3d target((corner & 1) - 0.5, ((corner >> 1) & 1) - 0.5, ((corner >> 2) & 1) - 0.5);
      for (double t : {-0.5, -0.25, 0.0, 0.3}) {
        Eigen::Vector3d on_edge = target;
        on_edge[axis] = t;
        const Eigen::Vector3d origin = on_edge * 6.0 + Eigen::Vector3d(0.01, 0.02, 0.03);
        const Ray ray = make_ray(origin, on_edge - origin, 20);
        const auto hit = rig->caster.cast(ray);
        expect_sane(hit, ray);
        ASSERT_TRUE(hit.has_value()) << on_edge.transpose();
        EXPECT_NEAR(hit->range_m, (on_edge - origin).norm(), 1e-6) << on_edge.transpose();
      }
    }
  }
  // From the centre (inside the closed mesh): the exit surface, like primitives.
  const auto inside = rig->caster.cast(make_ray({0, 0, 0}, {1, 0, 0}, 5));
  ASSERT_TRUE(inside.has_value());
  EXPECT_NEAR(inside->range_m, 0.5, 1e-9);
}

TEST(OdeMesh, QuadAndCube_SaneAnswers) {
  auto rig = rig_of<OdeRayCaster>({make_object(quad_mesh(), Eigen::Vector3d(3, 0, 0)),
                                   make_object(cube_mesh(), Eigen::Vector3d(0, 5, 0))});
  const auto quad_hit = rig->caster.cast(make_ray({0, 0.3, -0.2}, {1, 0, 0}, 10));
  ASSERT_TRUE(quad_hit.has_value());
  EXPECT_NEAR(quad_hit->range_m, 3.0, 1e-9);
  for (int k = -5; k <= 5; ++k) {
    const Ray ray = make_ray(Eigen::Vector3d(0, k * 1e-8, k * 1e-8), Eigen::Vector3d::UnitX(), 10);
    expect_sane(rig->caster.cast(ray), ray);  // on the diagonal: any sane answer
  }
}

}  // namespace
}  // namespace ldoem::raycast
