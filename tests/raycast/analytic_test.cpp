// Closed-form ground truth for plane, sphere, box and cylinder: both casters to 1e-9 m.
#include "caster_fixture.hpp"

#include <random>

namespace ldoem::raycast {
namespace {

using namespace ldoem::raycast::testing;

constexpr double kTolerance_m = 1e-9;
constexpr int kRaysPerShape = 2000;

struct ExpectedHit {
  double range_m;
  Eigen::Vector3d normal;  // outward
};

Eigen::Quaterniond random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
}

Eigen::Vector3d random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
}

// Sphere: |o + t d - c|^2 = R^2, nearest positive root (origin outside).
std::optional<ExpectedHit> sphere_truth(const Eigen::Vector3d& c, double radius, const Eigen::Vector3d& o,
                                     const Eigen::Vector3d& d) {
  const Eigen::Vector3d q = o - c;
  const double b = q.dot(d);
  const double disc = b * b - (q.squaredNorm() - radius * radius);
  if (disc < 0) return std::nullopt;
  const double t = -b - std::sqrt(disc);
  if (t <= 0) return std::nullopt;
  return ExpectedHit{t, (o + t * d - c).normalized()};
}

// Box: slab test in the box frame.
std::optional<ExpectedHit> box_truth(const Eigen::Vector3d& c, const Eigen::Quaterniond& q, const Eigen::Vector3d& size,
                                  const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  const Eigen::Vector3d lo = q.inverse() * (o - c);
  const Eigen::Vector3d ld = q.inverse() * d;
  double t_enter = -1e300, t_exit = 1e300;
  int axis = -1;
  for (int i = 0; i < 3; ++i) {
    const double h = size[i] / 2;
    if (ld[i] == 0) {
      if (std::abs(lo[i]) > h) return std::nullopt;
      continue;
    }
    double t1 = (-h - lo[i]) / ld[i], t2 = (h - lo[i]) / ld[i];
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > t_enter) { t_enter = t1; axis = i; }
    t_exit = std::min(t_exit, t2);
  }
  if (t_enter > t_exit || t_enter <= 0 || axis < 0) return std::nullopt;
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n[axis] = ld[axis] > 0 ? -1.0 : 1.0;
  return ExpectedHit{t_enter, q * n};
}

// Finite cylinder along local z with flat caps.
std::optional<ExpectedHit> cylinder_truth(const Eigen::Vector3d& c, const Eigen::Quaterniond& q, double radius,
                                       double length, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  const Eigen::Vector3d lo = q.inverse() * (o - c);
  const Eigen::Vector3d ld = q.inverse() * d;
  std::optional<ExpectedHit> best;
  auto consider = [&](double t, const Eigen::Vector3d& local_normal) {
    if (t > 0 && (!best || t < best->range_m)) best = ExpectedHit{t, q * local_normal};
  };
  const double a = ld.x() * ld.x() + ld.y() * ld.y();
  if (a > 0) {
    const double b = lo.x() * ld.x() + lo.y() * ld.y();
    const double disc = b * b - a * (lo.x() * lo.x() + lo.y() * lo.y() - radius * radius);
    if (disc >= 0) {
      const double t = (-b - std::sqrt(disc)) / a;
      const Eigen::Vector3d p = lo + t * ld;
      if (std::abs(p.z()) <= length / 2) consider(t, Eigen::Vector3d(p.x(), p.y(), 0).normalized());
    }
  }
  if (ld.z() != 0) {
    for (double side : {-1.0, 1.0}) {
      const double t = (side * length / 2 - lo.z()) / ld.z();
      const Eigen::Vector3d p = lo + t * ld;
      if (p.x() * p.x() + p.y() * p.y() <= radius * radius) consider(t, Eigen::Vector3d(0, 0, side));
    }
  }
  return best;
}

template <class Caster>
class AnalyticTest : public ::testing::Test {};
TYPED_TEST_SUITE(AnalyticTest, CasterTypes);

// Rays from random points on a 6 m sphere around the object, aimed at random points near it.
template <class Caster, class Truth>
void check_against_truth(Rig<Caster>& rig, const Eigen::Vector3d& centre, double aim_spread_m, Truth truth,
                         std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> spread(-aim_spread_m, aim_spread_m);
  int hits = 0;
  for (int i = 0; i < kRaysPerShape; ++i) {
    const Eigen::Vector3d origin = centre + 6.0 * random_unit(rng);
    const Eigen::Vector3d aim = centre + Eigen::Vector3d(spread(rng), spread(rng), spread(rng));
    const Ray ray = make_ray(origin, aim - origin, 100.0);
    const auto expected = truth(origin, ray.direction);
    const auto hit = rig.caster.cast(ray);
    expect_sane(hit, ray);
    ASSERT_EQ(hit.has_value(), expected.has_value()) << "ray " << i;
    if (!hit) continue;
    ++hits;
    EXPECT_NEAR(hit->range_m, expected->range_m, kTolerance_m) << "ray " << i;
    EXPECT_NEAR((hit->normal - expected->normal).norm(), 0.0, 1e-9) << "ray " << i;
    EXPECT_EQ(hit->object_index, 0u);
  }
  EXPECT_GT(hits, kRaysPerShape / 4);  // the sample exercises hits, not only misses
}

TYPED_TEST(AnalyticTest, Sphere_MatchesClosedForm) {
  const Eigen::Vector3d c(1.5, -2.0, 0.7);
  auto rig = rig_of<TypeParam>({make_object(scene::Sphere{0.8}, c)});
  check_against_truth(*rig, c, 1.0, [&](auto& o, auto& d) { return sphere_truth(c, 0.8, o, d); }, 11);
}

TYPED_TEST(AnalyticTest, RotatedBox_MatchesClosedForm) {
  std::mt19937_64 rng(5);
  const Eigen::Vector3d c(-1.0, 0.5, 2.0), size(0.6, 1.2, 0.3);
  const Eigen::Quaterniond q = random_rotation(rng);
  auto rig = rig_of<TypeParam>({make_object(scene::Box{size}, c, q)});
  check_against_truth(*rig, c, 0.8, [&](auto& o, auto& d) { return box_truth(c, q, size, o, d); }, 12);
}

TYPED_TEST(AnalyticTest, RotatedCylinder_MatchesClosedForm) {
  std::mt19937_64 rng(6);
  const Eigen::Vector3d c(0.2, 0.3, -0.4);
  const Eigen::Quaterniond q = random_rotation(rng);
  auto rig = rig_of<TypeParam>({make_object(scene::Cylinder{0.25, 1.1}, c, q)});
  check_against_truth(*rig, c, 0.7, [&](auto& o, auto& d) { return cylinder_truth(c, q, 0.25, 1.1, o, d); }, 13);
}

TYPED_TEST(AnalyticTest, Plane_MatchesClosedForm) {
  const Eigen::Vector3d normal = Eigen::Vector3d(0.2, -0.3, 1.0).normalized();
  const double offset_m = 0.4;
  auto rig = rig_of<TypeParam>({make_object(scene::Plane{normal, offset_m}, Eigen::Vector3d::Zero())});
  std::mt19937_64 rng(14);
  int hits = 0;
  for (int i = 0; i < kRaysPerShape; ++i) {
    const Eigen::Vector3d origin = 5.0 * random_unit(rng);
    const Ray ray = make_ray(origin, random_unit(rng), 100.0);
    const double denominator = normal.dot(ray.direction);
    const double t = (offset_m - normal.dot(origin)) / denominator;
    const bool expect_hit = t > 0 && t <= 100.0;
    const auto hit = rig->caster.cast(ray);
    expect_sane(hit, ray);
    ASSERT_EQ(hit.has_value(), expect_hit) << "ray " << i;
    if (!hit) continue;
    ++hits;
    EXPECT_NEAR(hit->range_m, t, kTolerance_m * std::max(1.0, t));
    const Eigen::Vector3d facing = denominator > 0 ? Eigen::Vector3d(-normal) : normal;
    EXPECT_NEAR((hit->normal - facing).norm(), 0.0, 1e-12);
  }
  EXPECT_GT(hits, kRaysPerShape / 4);
}

}  // namespace
}  // namespace ldoem::raycast
