// EmbreeRayCaster answers exactly what the reference OdeRayCaster answers on primitive scenes.
#include "caster_fixture.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>
#include <variant>
#include <vector>

namespace ldoem::raycast {
namespace {

using namespace ldoem::raycast::testing;

scene::Scene random_primitive_scene(std::uint64_t seed, int object_count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> position(-5.0, 5.0), size(0.05, 1.5), unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  scene::Scene s;
  for (int i = 0; i < object_count; ++i) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Eigen::Vector3d p(position(rng), position(rng), position(rng));
    // Built by a lambda, not assigned into a default Shape: g++ 12 then sees a moved-from Mesh
    // vector as maybe uninitialised (-Wmaybe-uninitialized, a false positive).
    const auto make_shape = [&]() -> scene::Shape {
      switch (i % 4) {
        case 0: return scene::Box{Eigen::Vector3d(size(rng), size(rng), size(rng))};
        case 1: return scene::Sphere{size(rng) / 2};
        case 2: return scene::Cylinder{size(rng) / 2, size(rng)};
        default: return scene::Capsule{size(rng) / 3, size(rng)};
      }
    };
    s.objects.push_back(make_object(make_shape(), p, q, unit(rng)));
  }
  s.objects.push_back(make_object(scene::Plane{Eigen::Vector3d(0.1, 0.0, 1.0).normalized(), -6.0}, Eigen::Vector3d::Zero()));
  return s;
}

std::vector<Ray> random_rays(std::uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> position(-8.0, 8.0), range(1.0, 40.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    rays.push_back(make_ray(Eigen::Vector3d(position(rng), position(rng), position(rng)),
                            Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)), range(rng)));
  }
  return rays;
}

// Each ray on its own, in order, on the calling thread.
void cast_each(const RayCaster& caster, const std::vector<Ray>& rays, std::vector<std::optional<Hit>>& hits) {
  for (std::size_t i = 0; i < rays.size(); ++i) hits[i] = caster.cast(rays[i]);
}

void expect_same(const std::optional<Hit>& reference, const std::optional<Hit>& fast, std::size_t i) {
  ASSERT_EQ(reference.has_value(), fast.has_value()) << "ray " << i;
  if (!reference) return;
  EXPECT_EQ(reference->object_index, fast->object_index) << "ray " << i;
  EXPECT_NEAR(reference->range_m, fast->range_m, 1e-9) << "ray " << i;
  // Both normals are exact to rounding, but rounded differently: ODE takes the contact point in
  // world coordinates and solves the textbook quadratic, EmbreeRayCaster works in the object's
  // frame around the point of closest approach. Near grazing incidence they differ by ~1e-12.
  EXPECT_NEAR((reference->normal - fast->normal).norm(), 0.0, 1e-10) << "ray " << i;
  EXPECT_EQ(reference->reflectance, fast->reflectance) << "ray " << i;
}

class EquivalenceTest : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(EquivalenceTest, RandomPrimitiveScene_EmbreeEqualsOde) {
  const scene::Scene s = random_primitive_scene(GetParam(), 60);
  const OdeWorld world(s);
  const OdeRayCaster reference(world);
  const EmbreeRayCaster fast(world);
  const auto rays = random_rays(GetParam() * 7919 + 1, 20000);
  int hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto expected = reference.cast(rays[i]);
    hits += expected.has_value();
    expect_same(expected, fast.cast(rays[i]), i);
    if (::testing::Test::HasFailure()) return;  // one ray's report is enough
  }
  EXPECT_GT(hits, 2000);
}

INSTANTIATE_TEST_SUITE_P(Seeds, EquivalenceTest, ::testing::Values(1u, 2u, 3u, 4u, 5u));

// Boxes square to the world take a shortcut in EmbreeRayCaster (no rotation into the box's
// frame), and rays starting inside a solid must report its exit surface as ODE does: both, on
// every primitive kind, from origins inside, on the edge of and just outside each solid.
TEST(EmbreePrimitives, AlignedBoxesAndRaysFromInside_EmbreeEqualsOde) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> position(-4.0, 4.0), size(0.2, 1.5), unit(-1.0, 1.0), spread(0.0, 1.3);
  std::normal_distribution<double> gauss(0.0, 1.0);
  scene::Scene s;
  for (int i = 0; i < 24; ++i) {
    const Eigen::Quaterniond q = i % 8 == 0 ? Eigen::Quaterniond::Identity()
                                            : Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Eigen::Vector3d p(position(rng), position(rng), position(rng));
    const auto make_shape = [&]() -> scene::Shape {
      switch (i % 4) {
        case 0: return scene::Box{Eigen::Vector3d(size(rng), size(rng), size(rng))};
        case 1: return scene::Sphere{size(rng) / 2};
        case 2: return scene::Cylinder{size(rng) / 2, size(rng)};
        default: return scene::Capsule{size(rng) / 3, size(rng)};
      }
    };
    s.objects.push_back(make_object(make_shape(), p, i % 2 == 0 ? Eigen::Quaterniond::Identity() : q, 0.5));
  }
  const OdeWorld world(s);
  const OdeRayCaster reference(world);
  const EmbreeRayCaster fast(world);
  int rays = 0, from_inside = 0;
  for (const auto& object : s.objects) {
    // ODE 0.16 misses some exits of rays starting inside a capsule (next test): not compared here.
    if (std::holds_alternative<scene::Capsule>(object.shape)) continue;
    for (int k = 0; k < 400; ++k) {
      // Origins around the object's centre, up to 1.3 sizes out: many inside, some outside.
      const Eigen::Vector3d origin = object.pose.position_m + spread(rng) * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      const Ray ray = make_ray(origin, Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)), 20.0);
      const auto expected = reference.cast(ray);
      from_inside += expected && expected->range_m < 0.8;
      expect_same(expected, fast.cast(ray), static_cast<std::size_t>(rays++));
      if (::testing::Test::HasFailure()) return;
    }
  }
  EXPECT_GT(from_inside, rays / 4);
}

double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// From inside a capsule, ODE 0.16's dCollideRayCapsule gives up when the ray would leave the
// infinite cylinder only beyond its length, even if it leaves the capsule through a rounded end
// first (a ray nearly along the axis). EmbreeRayCaster reports that exit. Checked here against
// the definition: the hit lies on the capsule's surface (at radius from its axis segment) and
// the ray is inside just before it; wherever ODE does answer, the two agree.
TEST(EmbreePrimitives, RaysFromInsideCapsules_ReportTheExitSurface) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.2, 1.5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  int rays = 0, ode_answers = 0;
  for (int c = 0; c < 12; ++c) {
    const double radius_m = size(rng) / 3, length_m = size(rng);
    const Eigen::Quaterniond q = Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
    const Eigen::Vector3d centre(unit(rng), unit(rng), unit(rng));
    auto ode = rig_of<OdeRayCaster>({make_object(scene::Capsule{radius_m, length_m}, centre, q)});
    const EmbreeRayCaster fast(ode->world);
    const Eigen::Vector3d axis = q * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d a = centre - 0.5 * length_m * axis, b = centre + 0.5 * length_m * axis;
    for (int k = 0; k < 500; ++k) {
      // Inside: a point of the axis segment plus less than the radius; directions near the axis
      // half of the time (where ODE gives up).
      const Eigen::Vector3d origin = a + (0.5 + 0.5 * unit(rng)) * (b - a) + 0.5 * radius_m * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
      const Eigen::Vector3d direction = k % 2 == 0 ? Eigen::Vector3d(axis + 0.05 * Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)))
                                                   : Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
      const Ray ray = make_ray(origin, direction, 10.0);
      const auto hit = fast.cast(ray);
      ++rays;
      ASSERT_TRUE(hit.has_value()) << k;
      expect_sane(hit, ray);
      const Eigen::Vector3d at = ray.origin_m + hit->range_m * ray.direction;
      EXPECT_NEAR(distance_to_segment(at, a, b), radius_m, 1e-9) << k;
      EXPECT_LT(distance_to_segment(at - 1e-6 * ray.direction, a, b), radius_m) << k;
      const auto expected = ode->caster.cast(ray);
      if (!expected) continue;
      ++ode_answers;
      expect_same(expected, hit, static_cast<std::size_t>(k));
      if (::testing::Test::HasFailure()) return;
    }
  }
  EXPECT_GT(ode_answers, rays / 3);
}

TEST(EmbreeThreads, TwoThreads_GiveTheSerialAnswers) {
  const scene::Scene s = random_primitive_scene(9, 40);
  const OdeWorld world(s);
  const EmbreeRayCaster caster(world);
  const auto rays = random_rays(99, 4000);
  std::vector<std::optional<Hit>> serial(rays.size());
  cast_each(caster, rays, serial);
  std::vector<std::optional<Hit>> parallel(rays.size());
  auto work = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) parallel[i] = caster.cast(rays[i]);
  };
  std::thread first(work, 0, rays.size() / 2);
  std::thread second(work, rays.size() / 2, rays.size());
  first.join();
  second.join();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(serial[i].has_value(), parallel[i].has_value()) << i;
    if (serial[i]) {
      EXPECT_EQ(serial[i]->range_m, parallel[i]->range_m) << i;
    }
  }
}

// Rays whose answer from a plane is a close call: origins on or within 1e-15..100 m of the
// plane, directions parallel or nearly so, lengths ending just before, at or after the hit.
// EmbreeRayCaster answers planes with its own arithmetic; it must agree with ODE on each one.
std::vector<Ray> rays_near_plane(const Eigen::Vector3d& normal, double offset_m) {
  const Eigen::Vector3d tangent = normal.unitOrthogonal();
  const Eigen::Vector3d bases[] = {offset_m * normal, offset_m * normal + 3.7 * tangent + 1.3 * normal.cross(tangent)};
  const double heights_m[] = {0.0, 1e-15, -1e-15, 1e-12, -1e-12, 1e-9, -1e-9, 1e-6, -1e-6, 1e-3, -1e-3, 1.0, -1.0, 100.0, -100.0};
  const double slopes[] = {0.0, 1e-16, -1e-16, 1e-14, -1e-14, 1e-12, -1e-12, 1e-10, -1e-10, 1e-6, -1e-6, 0.3, -0.3, 1e6, -1e6};
  std::vector<Ray> rays;
  for (const Eigen::Vector3d& base : bases) {
    for (double height_m : heights_m) {
      for (double slope : slopes) {
        const Eigen::Vector3d origin = base + height_m * normal;
        const Eigen::Vector3d direction = (tangent + slope * normal).normalized();
        const double hit_m = -height_m / direction.dot(normal);
        std::vector<double> lengths_m = {1.0, 1e6};
        if (std::isfinite(hit_m) && hit_m > 0.0 && hit_m < 1e8) {
          for (double factor : {1.0 - 1e-12, 1.0 - 1e-15, 1.0, 1.0 + 1e-15, 1.0 + 1e-12}) lengths_m.push_back(factor * hit_m);
        }
        for (double length_m : lengths_m) rays.push_back(Ray{origin, direction, length_m, 0.0});
      }
    }
  }
  return rays;
}

TEST(EmbreePlanes, CloseCallsNearPlanes_EmbreeEqualsOde) {
  const std::vector<scene::SceneObject> planes = {
      make_object(scene::Plane{Eigen::Vector3d::UnitZ(), 0.0}, Eigen::Vector3d::Zero()),
      make_object(scene::Plane{Eigen::Vector3d(0.3, -0.2, 1.0).normalized(), 2.5}, Eigen::Vector3d::Zero()),
      make_object(scene::Plane{Eigen::Vector3d(1.0, 1.0, 1.0).normalized(), -3.0}, Eigen::Vector3d::Zero()),
      make_object(scene::Plane{Eigen::Vector3d(-1.0, 0.0, 0.0), 1e5}, Eigen::Vector3d::Zero()),
  };
  for (const bool with_box : {false, true}) {  // planes alone, and beside a BVH
    for (const scene::SceneObject& plane : planes) {
      std::vector<scene::SceneObject> objects = {plane};
      if (with_box) objects.push_back(make_object(scene::Box{Eigen::Vector3d(1, 2, 3)}, Eigen::Vector3d(0, 0, 20)));
      auto ode = rig_of<OdeRayCaster>(objects);
      const EmbreeRayCaster fast(ode->world);
      const auto& shape = std::get<scene::Plane>(plane.shape);
      const auto rays = rays_near_plane(shape.normal, shape.offset_m);
      int hits = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const auto expected = ode->caster.cast(rays[i]);
        hits += expected.has_value();
        expect_same(expected, fast.cast(rays[i]), i);
        if (::testing::Test::HasFailure()) return;
      }
      EXPECT_GT(hits, 100);
      EXPECT_LT(hits, static_cast<int>(rays.size()) - 100);
    }
  }
}

// Every thread casts with its own ODE ray geom, shared by all casters on that thread: casters
// taking turns on one thread, and threads that come and go, give the answers of a lone caster.
TEST(EmbreeThreads, CastersTakingTurnsAndShortLivedThreads_GiveTheSerialAnswers) {
  const scene::Scene first_scene = random_primitive_scene(11, 30);
  const scene::Scene second_scene = random_primitive_scene(12, 30);
  const OdeWorld first_world(first_scene);
  const OdeWorld second_world(second_scene);
  const EmbreeRayCaster first(first_world);
  const OdeRayCaster second(second_world);
  const auto rays = random_rays(77, 2000);
  std::vector<std::optional<Hit>> first_alone(rays.size()), second_alone(rays.size());
  cast_each(first, rays, first_alone);
  cast_each(second, rays, second_alone);
  for (std::size_t i = 0; i < rays.size(); ++i) {  // taking turns on this thread
    expect_same(first_alone[i], first.cast(rays[i]), i);
    expect_same(second_alone[i], second.cast(rays[i]), i);
  }
  int threads_with_a_mismatch = 0;
  for (int round = 0; round < 8; ++round) {  // threads that start, cast a little and exit
    std::vector<std::optional<Hit>> answers(rays.size());
    std::thread worker([&] { cast_each(first, rays, answers); });
    worker.join();
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const bool same = answers[i].has_value() == first_alone[i].has_value() &&
                        (!answers[i] || answers[i]->range_m == first_alone[i]->range_m);
      if (!same) {
        ++threads_with_a_mismatch;
        break;
      }
    }
  }
  EXPECT_EQ(threads_with_a_mismatch, 0);
}

}  // namespace
}  // namespace ldoem::raycast
