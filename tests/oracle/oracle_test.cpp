// The oracle pinned on closed-form cases: each expected range is computed here independently,
// from its textbook formula in MPFR at 256 bits, and the oracle's double-double must agree to
// 1e-30 relative. Plus the decisions it reports: ties, tangents, the reach, rays from inside.
#include "oracle.hpp"

#include <gtest/gtest.h>
#include <mpfr.h>

#include <cmath>
#include <vector>

namespace ldoem::oracle {
namespace {

// A 256-bit MPFR number with the few operations the formulas below need.
class Big {
 public:
  Big(double v = 0.0) {  // NOLINT: doubles convert exactly
    mpfr_init2(x_, 256);
    mpfr_set_d(x_, v, MPFR_RNDN);
  }
  Big(const Big& o) {
    mpfr_init2(x_, 256);
    mpfr_set(x_, o.x_, MPFR_RNDN);
  }
  Big& operator=(const Big& o) {
    mpfr_set(x_, o.x_, MPFR_RNDN);
    return *this;
  }
  ~Big() { mpfr_clear(x_); }
  friend Big operator+(const Big& a, const Big& b) { return op(a, b, mpfr_add); }
  friend Big operator-(const Big& a, const Big& b) { return op(a, b, mpfr_sub); }
  friend Big operator*(const Big& a, const Big& b) { return op(a, b, mpfr_mul); }
  friend Big operator/(const Big& a, const Big& b) { return op(a, b, mpfr_div); }
  friend Big sqrt(const Big& a) {
    Big r;
    mpfr_sqrt(r.x_, a.x_, MPFR_RNDN);
    return r;
  }
  // |(hi + lo) - this| / |this|, in double.
  double relative_error(double hi, double lo) const {
    const Big diff = (Big(hi) + Big(lo)) - *this;
    return std::abs(mpfr_get_d(diff.x_, MPFR_RNDN) / mpfr_get_d(x_, MPFR_RNDN));
  }

 private:
  static Big op(const Big& a, const Big& b, int (*f)(mpfr_ptr, mpfr_srcptr, mpfr_srcptr, mpfr_rnd_t)) {
    Big r;
    f(r.x_, a.x_, b.x_, MPFR_RNDN);
    return r;
  }
  mpfr_t x_;
};

Part sphere(Vec centre, double r, std::uint32_t object = 0) {
  Part p;
  p.kind = Kind::sphere;
  p.centre = centre;
  p.radius = r;
  p.object = object;
  return p;
}

void expect_pinned(const Part& part, const OracleRay& ray, const Big& expected) {
  const PartAnswer exact = cast_part(part, ray, 0.0, true);
  ASSERT_TRUE(exact.hit);
  EXPECT_LT(expected.relative_error(exact.range_m, exact.range_tail_m), 1e-30) << exact_range_text(part, ray);
  // The floating filter encloses the same number.
  const PartAnswer filtered = cast_part(part, ray);
  ASSERT_TRUE(filtered.hit);
  EXPECT_LE(std::abs(filtered.range_m - exact.range_m), filtered.range_error_m + 1e-300);
}

TEST(Oracle, Sphere_RangeToTheClosedFormWithin1e30) {
  // Ray along x from the origin past a unit sphere at (5, y, 0): 5 - sqrt(1 - y^2).
  const double y = 0.3;
  expect_pinned(sphere({5, y, 0}, 1.0), OracleRay{{0, 0, 0}, {1, 0, 0}, 10}, Big(5) - sqrt(Big(1) - Big(y) * Big(y)));
  // A non-unit direction: closest approach c = s.d/|d|, range c - sqrt(r^2 - (|s|^2 - c^2)).
  const Vec d{1.0, 1e-3, 2e-3};
  const Big length = sqrt(Big(d[0]) * Big(d[0]) + Big(d[1]) * Big(d[1]) + Big(d[2]) * Big(d[2]));
  const Big along = (Big(7) * Big(d[0]) + Big(0.01) * Big(d[1])) / length;
  const Big squared = Big(7) * Big(7) + Big(0.01) * Big(0.01);
  expect_pinned(sphere({7, 0.01, 0}, 0.25), OracleRay{{0, 0, 0}, d, 20}, along - sqrt(Big(0.25) * Big(0.25) - (squared - along * along)));
}

TEST(Oracle, Cylinder_SideAndCapWithin1e30) {
  Part c;
  c.kind = Kind::cylinder;
  c.centre = {0, 0, 10};
  c.radius = 0.5;
  c.half_length = 2.0;
  // Across the side at x = 0.1, z = 10.2: enters at y = -sqrt(r^2 - x^2), from y = -3.
  expect_pinned(c, OracleRay{{0.1, -3, 10.2}, {0, 1, 0}, 10}, Big(3) - sqrt(Big(0.25) - Big(0.1) * Big(0.1)));
  // Along the axis onto the cap at z = 8.
  expect_pinned(c, OracleRay{{0.1, 0.2, 0}, {0, 0, 1}, 10}, Big(8));
}

TEST(Oracle, Capsule_EndBallWithin1e30) {
  Part c;
  c.kind = Kind::capsule;
  c.radius = 0.5;
  c.half_length = 1.0;
  // Up the axis from z = -5 at (0.1, 0.2): the lower ball, z = -1 - sqrt(r^2 - x^2 - y^2).
  const Big off = Big(0.1) * Big(0.1) + Big(0.2) * Big(0.2);
  expect_pinned(c, OracleRay{{0.1, 0.2, -5}, {0, 0, 1}, 10}, Big(4) - sqrt(Big(0.25) - off));
}

TEST(Oracle, Box_RotatedAndSlantedWithin1e30) {
  Part b;
  b.kind = Kind::box;
  b.centre = {10, 0, 0};
  b.half = {1, 2, 3};
  // Enters the face x = 9 along (1, 0.1, 0.05): l = 9, range 9 |d|.
  const Vec d{1, 0.1, 0.05};
  const Big length = sqrt(Big(1) + Big(0.1) * Big(0.1) + Big(0.05) * Big(0.05));
  expect_pinned(b, OracleRay{{0, 0, 0}, d, 20}, Big(9) * length);
  // The same box turned a quarter about z (local x along world y): its y half (2) faces x.
  b.rotation = {0, -1, 0, 1, 0, 0, 0, 0, 1};
  expect_pinned(b, OracleRay{{0, 0, 0}, d, 20}, Big(8) * length);
}

TEST(Oracle, Triangle_PlaneRangeWithin1e30) {
  Part t;
  t.kind = Kind::triangle;
  t.vertices = {Vec{3, -1, -1}, Vec{3, 2, -1}, Vec{3.5, -1, 2}};
  const Vec d{1, 0.1, 0.2};
  // Plane through a with normal n = (b - a) x (c - a): range n.(a - o) / (n.d) * |d|.
  const Big e1[3] = {Big(0), Big(3), Big(0)}, e2[3] = {Big(0.5), Big(0), Big(3)};
  const Big n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
  const Big na = n[0] * Big(3) + n[1] * Big(-1) + n[2] * Big(-1);
  const Big nd = n[0] * Big(d[0]) + n[1] * Big(d[1]) + n[2] * Big(d[2]);
  const Big length = sqrt(Big(d[0]) * Big(d[0]) + Big(d[1]) * Big(d[1]) + Big(d[2]) * Big(d[2]));
  expect_pinned(t, OracleRay{{0, 0, 0}, d, 20}, na / nd * length);
}

TEST(Oracle, CoincidentSpheres_TieToTheLowerObject) {
  const std::vector<Part> parts{sphere({5, 0, 0}, 0.5, 3), sphere({5, 0, 0}, 0.5, 1)};
  const Answer a = cast(parts, OracleRay{{0, 0, 0}, {1, 0.1, 0}, 20});
  ASSERT_TRUE(a.hit);
  EXPECT_TRUE(a.tie);
  EXPECT_EQ(a.object, 1u);
  // Nearly coincident (one ulp of radius apart): no tie, the bigger one is nearer.
  const std::vector<Part> apart{sphere({5, 0, 0}, 0.5, 3), sphere({5, 0, 0}, std::nextafter(0.5, 1.0), 7)};
  const Answer b = cast(apart, OracleRay{{0, 0, 0}, {1, 0.1, 0}, 20});
  EXPECT_FALSE(b.tie);
  EXPECT_EQ(b.object, 7u);
}

TEST(Oracle, Tangents_TouchHitsNextDoubleMisses) {
  const Part s = sphere({5, 1, 0}, 1.0);
  const PartAnswer touch = cast_part(s, OracleRay{{0, 0, 0}, {1, 0, 0}, 10});
  ASSERT_TRUE(touch.hit);
  EXPECT_TRUE(touch.boundary);
  EXPECT_EQ(touch.range_m, 5.0);
  EXPECT_FALSE(cast_part(s, OracleRay{{0, -1e-60, 0}, {1, 0, 0}, 10}).hit);
  EXPECT_TRUE(cast_part(s, OracleRay{{0, 1e-60, 0}, {1, 0, 0}, 10}).hit);
  // A ray through a triangle's edge hits it, and says so.
  Part t;
  t.kind = Kind::triangle;
  t.vertices = {Vec{3, -1, -1}, Vec{3, 1, -1}, Vec{3, 0, 1}};
  const PartAnswer edge = cast_part(t, OracleRay{{0, 0.2, -1}, {1, 0, 0}, 10});
  EXPECT_TRUE(edge.hit && edge.boundary);
  EXPECT_FALSE(cast_part(t, OracleRay{{0, 0.2, std::nextafter(-1.0, -2.0)}, {1, 0, 0}, 10}).hit);
  // Grown by 1e-9 m the triangle takes a ray passing 1e-10 m outside it.
  EXPECT_TRUE(cast_part(t, OracleRay{{0, 0.2, -1 - 1e-10}, {1, 0, 0}, 10}, 1e-9).hit);
}

TEST(Oracle, Reach_HitExactlyAtReachCountsOneUlpShortDoesNot) {
  Part b;
  b.kind = Kind::box;
  b.centre = {10, 0, 0};
  b.half = {1, 1, 1};
  const std::vector<Part> parts{b};
  const Answer at = cast(parts, OracleRay{{0, 0, 0}, {1, 0, 0}, 9.0});
  EXPECT_TRUE(at.hit && at.at_reach);
  EXPECT_FALSE(cast(parts, OracleRay{{0, 0, 0}, {1, 0, 0}, std::nextafter(9.0, 0.0)}).hit);
}

TEST(Oracle, Inside_ExitSurfaceAndOriginOnSurfaceGivesNothing) {
  const Part s = sphere({0, 0, 0}, 2.0);
  const PartAnswer exit = cast_part(s, OracleRay{{0.5, 0, 0}, {1, 0, 0}, 10});
  ASSERT_TRUE(exit.hit);
  EXPECT_EQ(exit.range_m, 1.5);
  EXPECT_FALSE(cast_part(s, OracleRay{{-2, 0, 0}, {1, 0, 0}, 10}).hit);  // on the surface, inwards
  EXPECT_FALSE(cast_part(s, OracleRay{{2, 0, 0}, {1, 0, 0}, 10}).hit);   // on the surface, outwards
  Part plane;
  plane.kind = Kind::plane;
  plane.normal = {0, 0, 1};
  plane.offset = 0;
  EXPECT_FALSE(cast_part(plane, OracleRay{{0, 0, 1}, {1, 0, 0}, 10}).hit);  // parallel
  EXPECT_EQ(cast_part(plane, OracleRay{{0, 0, -1}, {0, 0, 1}, 10}).range_m, 1.0);  // from below too
}

}  // namespace
}  // namespace ldoem::oracle
