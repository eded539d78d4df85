// EmbreeRayCaster answers exactly what the reference OdeRayCaster answers on primitive scenes.
#include "caster_fixture.hpp"

#include <random>
#include <thread>

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
    scene::Shape shape;
    switch (i % 4) {
      case 0: shape = scene::Box{Eigen::Vector3d(size(rng), size(rng), size(rng))}; break;
      case 1: shape = scene::Sphere{size(rng) / 2}; break;
      case 2: shape = scene::Cylinder{size(rng) / 2, size(rng)}; break;
      default: shape = scene::Capsule{size(rng) / 3, size(rng)}; break;
    }
    s.objects.push_back(make_object(shape, p, q, unit(rng)));
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

void expect_same(const std::optional<Hit>& reference, const std::optional<Hit>& fast, std::size_t i) {
  ASSERT_EQ(reference.has_value(), fast.has_value()) << "ray " << i;
  if (!reference) return;
  EXPECT_EQ(reference->object_index, fast->object_index) << "ray " << i;
  EXPECT_NEAR(reference->range_m, fast->range_m, 1e-9) << "ray " << i;
  EXPECT_NEAR((reference->normal - fast->normal).norm(), 0.0, 1e-12) << "ray " << i;
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

TEST(EmbreeThreads, TwoThreads_GiveTheSerialAnswers) {
  const scene::Scene s = random_primitive_scene(9, 40);
  const OdeWorld world(s);
  const EmbreeRayCaster caster(world);
  const auto rays = random_rays(99, 4000);
  std::vector<std::optional<Hit>> serial(rays.size());
  caster.cast_many(rays, serial);
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

}  // namespace
}  // namespace ldoem::raycast
