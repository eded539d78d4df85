// Holds one caster answer against the exact oracle, within the bounds docs/numerics.md states
// and derives ("Error bounds"). Both the differential fuzzer and the seeded sweep of
// scripts/numerics-report judge with this, so the report and the fuzzer check the same claim.
#pragma once

#include "oracle.hpp"

#include <cstdint>
#include <span>
#include <string>

namespace ldoem::oracle {

// Which caster answered: the static one (Embree BVH, double-precision primitives, Embree's
// float triangles with the range recomputed in double) or the moving-world one (primitives in
// double in the object's frame, meshes as Embree's float triangles in the object's frame with the
// range recomputed in double from the world triangle's plane).
enum class Engine : std::uint8_t { embree, moving };

// What the bounds need to know of a part beyond its geometry: the point its arithmetic is
// relative to (a primitive's centre; for Embree's triangles the centre of the scene's float
// frame; for the moving caster's, the object's origin) and its size there.
struct PartScale {
  Vec reference{};
  double size_m = 0.0;
};

// u: the unit roundoff of double; u_float: of float (Embree's and ODE's trimesh arithmetic).
inline constexpr double kDoubleRoundoff = 0x1p-53;
inline constexpr double kFloatRoundoff = 0x1p-24;
// The error-analysis constants of docs/numerics.md: about twice the number of roundings on the
// longest path of each computation.
inline constexpr double kDoubleOps = 64.0;
inline constexpr double kFloatOps = 16.0;
// A plane whose |n . d| is at most this is parallel to the ray within the casters' rounding of
// that product (~4 u; the judge's own cosine another ~4 u; doubled): whether it is hit is not
// decided (docs/numerics.md "Error bounds", planes).
inline constexpr double kPlaneParallelCosine = 16.0 * kDoubleRoundoff;

// The bound the caster promises on |range - exact range| for a hit on `part` at (about) range
// t: K u (P + S + t) / cos, P = |origin - reference|, S the part's size, cos the cosine of the
// incidence (at least sqrt(K u) on curved surfaces, where the half chord's square root caps
// the loss), u the roundoff of the arithmetic that produced the range.
double range_bound(const Part& part, const PartScale& scale, const OracleRay& ray, double t, Engine engine);
// How far the part's boundary may be misplaced (grown or shrunk) by the caster's arithmetic: a
// ray passing that close to an edge or a tangent may hit or miss.
double boundary_bound(const Part& part, const PartScale& scale, const OracleRay& ray, double t, Engine engine);
// Embree's float normal of a triangle is a cross product of its edges, rounded by ~2 u_float
// L^2 (L its longest edge), which on a sliver (twice the area 2A much less than L^2) is a large
// part of it; the float distance moves by that times the hit's distance from a vertex (<= L)
// over 2A cos: 8 u_float L^3 / (2A cos) (infinite for a degenerate triangle; 0 for other
// parts). Part of a triangle's order bound (docs/numerics.md "Error bounds").
double float_normal_error(const Part& part, const OracleRay& ray, double t);
// The bound on choosing between a triangle and another surface (Embree compares float
// distances; the moving caster compares a mesh's with the reach its query gets, the range of the
// nearest object found so far).
double order_bound(const Part& part, const PartScale& scale, const OracleRay& ray, double t, Engine engine);
// The moving caster's float test sees a mesh's triangle unrounded (pose + R v), its double range
// and the oracle see it rounded to double: how far along the ray that moves a hit (0 for other
// engines and parts). Part of the triangle's boundary and order bounds.
double pose_rounding(const Part& part, const PartScale& scale, const OracleRay& ray, double t, Engine engine);

struct CasterAnswer {
  bool hit = false;
  std::uint32_t object = 0;
  double range_m = 0.0;
};

enum class Fault : std::uint8_t { none, not_finite, wrong_object, range, missed, oracle_failed };
const char* fault_name(Fault fault);

struct Verdict {
  Fault fault = Fault::none;
  std::string what;  // for a fault: what disagreed, with numbers
  // For a hit accepted on a part: that part's kind, the error against its exact range, the
  // bound it was held to, and the error in ulps of the exact range.
  bool measured = false;
  Kind kind = Kind::box;
  std::size_t part = 0;
  double error_m = 0.0;
  double bound_m = 0.0;
  double ulps = 0.0;
  double cosine = 0.0;   // of the incidence on that part
  bool excused = false;  // accepted only because the ray is within the bound of a boundary, tie or the reach
  bool exact = false;    // the oracle needed its exact numbers (the filter could not decide)
};

// `reach` of the ray is the caster's (after its 1e9 m cap); ignored: OracleRay::ignored_object.
Verdict judge(std::span<const Part> parts, std::span<const PartScale> scales, const OracleRay& ray, std::uint32_t ignored,
              const CasterAnswer& answer, Engine engine);

}  // namespace ldoem::oracle
