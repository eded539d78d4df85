#include "judge.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace ldoem::oracle {
namespace {

double norm(const Vec& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
Vec minus(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec unit(const Vec& v) {
  const double n = norm(v);
  return n > 0 ? Vec{v[0] / n, v[1] / n, v[2] / n} : Vec{0, 0, 0};
}

struct Incidence {
  double cosine;  // |normal . direction| at the hit point
  bool curved;    // a quadric's side: the error of its half chord is capped by a square root
};

// The surface normal where the ray meets `part` at range t (in double: only the bound uses it).
// Within `edge_gap` of an edge of a box or a cylinder, the least cosine of the faces there.
Incidence incidence(const Part& part, const OracleRay& ray, double t, double edge_gap = 0.0) {
  const Vec d = unit(ray.direction);
  if (part.kind == Kind::plane) return {std::abs(dot(unit(part.normal), d)), false};
  if (part.kind == Kind::triangle) {
    const auto& v = part.vertices;
    return {std::abs(dot(unit(cross(minus(v[1], v[0]), minus(v[2], v[0]))), d)), false};
  }
  const auto& r = part.rotation;
  // The hit point relative to the centre, (o - centre) + t d: in world coordinates it would be
  // rounded by u |o| (1e-10 m for a scene 1e6 m out), enough to take a hit 3e-11 m from a
  // cylinder's rim for one on its side ("Findings" 13). Relative, it is off by a few u (P + t),
  // within which the faces of an edge are not told apart: the least cosine of both is taken.
  const Vec s = minus(ray.origin, part.centre);
  const Vec w{s[0] + t * d[0], s[1] + t * d[1], s[2] + t * d[2]};
  edge_gap += 8.0 * kDoubleRoundoff * (norm(s) + std::abs(t));
  const Vec u{r[0] * w[0] + r[3] * w[1] + r[6] * w[2], r[1] * w[0] + r[4] * w[1] + r[7] * w[2],
              r[2] * w[0] + r[5] * w[1] + r[8] * w[2]};
  const Vec dl{r[0] * d[0] + r[3] * d[1] + r[6] * d[2], r[1] * d[0] + r[4] * d[1] + r[7] * d[2],
               r[2] * d[0] + r[5] * d[1] + r[8] * d[2]};
  switch (part.kind) {
    case Kind::box: {
      int face = 0;
      double closest = std::numeric_limits<double>::infinity();
      for (int i = 0; i < 3; ++i) {
        const double gap = std::abs(part.half[i] - std::abs(u[i]));
        if (gap < closest) {
          closest = gap;
          face = i;
        }
      }
      double cosine = std::abs(dl[face]);
      for (int i = 0; i < 3; ++i) {
        if (std::abs(part.half[i] - std::abs(u[i])) <= closest + edge_gap) cosine = std::min(cosine, std::abs(dl[i]));
      }
      return {cosine, false};
    }
    case Kind::sphere:
      return {std::abs(dot(unit(u), dl)), true};
    case Kind::cylinder: {
      const double side_gap = std::abs(std::hypot(u[0], u[1]) - part.radius);
      const double cap_gap = std::abs(std::abs(u[2]) - part.half_length);
      const double cap = std::abs(dl[2]), side = std::abs(dot(unit(Vec{u[0], u[1], 0.0}), dl));
      if (std::abs(cap_gap - side_gap) <= edge_gap) return {std::min(cap, side), cap > side};
      if (cap_gap < side_gap) return {cap, false};
      return {side, true};
    }
    case Kind::capsule: {
      const double axis = std::clamp(u[2], -part.half_length, part.half_length);
      return {std::abs(dot(unit(Vec{u[0], u[1], u[2] - axis}), dl)), true};
    }
    default:
      return {1.0, false};
  }
}

double magnitude(const Part& part, const PartScale& scale, const OracleRay& ray, double t) {
  const double from_reference = part.kind == Kind::plane ? norm(ray.origin) + std::abs(part.offset)
                                                         : norm(minus(ray.origin, scale.reference));
  return from_reference + scale.size_m + std::abs(t);
}

// Embree's triangles (both casters': the moving one's meshes go through mesh_index.cpp since
// issue 26): the range is recomputed in double from the triangle's plane unless the ray grazes
// it (|n . d| <= 1e-6), then Embree's float distance stays.
constexpr double kEmbreeRefineCosine = 1e-6;

bool float_range(const Part& part, const OracleRay& ray, double t, Engine engine) {
  if (part.kind != Kind::triangle) return false;
  (void)engine;
  return incidence(part, ray, t).cosine <= kEmbreeRefineCosine;
}

// Distance from x to the closed triangle (double precision; the judge's tolerance only).
double triangle_distance(const Vec& x, const std::array<Vec, 3>& v) {
  const Vec ab = minus(v[1], v[0]), ac = minus(v[2], v[0]), ap = minus(x, v[0]);
  const Vec n = cross(ab, ac);
  const double nn = dot(n, n);
  double best = std::numeric_limits<double>::infinity();
  if (nn > 0) {  // inside the prism over the triangle: the distance to its plane
    const Vec b = cross(ap, ac), c = cross(ab, ap);
    const double wb = dot(b, n) / nn, wc = dot(c, n) / nn;
    if (wb >= 0 && wc >= 0 && wb + wc <= 1) best = std::abs(dot(ap, n)) / std::sqrt(nn);
  }
  for (int e = 0; e < 3; ++e) {  // else the nearest point of an edge (also for degenerate triangles)
    const Vec& a = v[e];
    const Vec ed = minus(v[(e + 1) % 3], a);
    const double len = dot(ed, ed);
    const double s = len > 0 ? std::clamp(dot(minus(x, a), ed) / len, 0.0, 1.0) : 0.0;
    const Vec p{a[0] + s * ed[0], a[1] + s * ed[1], a[2] + s * ed[2]};
    best = std::min(best, norm(minus(x, p)));
  }
  return best;
}

double ulp(double x) {
  x = std::abs(x);
  return std::nextafter(x, std::numeric_limits<double>::infinity()) - x;
}

}  // namespace

double range_bound(const Part& part, const PartScale& scale, const OracleRay& ray, double t, Engine engine) {
  const Incidence in = incidence(part, ray, t);
  const bool single = !float_range(part, ray, t, engine);
  const double k_u = single ? kDoubleOps * kDoubleRoundoff : kFloatOps * kFloatRoundoff;
  const double cosine = in.curved ? std::max(in.cosine, std::sqrt(k_u)) : in.cosine;
  // Embree's float distance (a grazing triangle's range) carries its float normal's error.
  return k_u * magnitude(part, scale, ray, t) / cosine + (single ? 0.0 : float_normal_error(part, ray, t));
}

double boundary_bound(const Part& part, const PartScale& scale, const OracleRay& ray, double t, Engine engine) {
  if (part.kind != Kind::triangle) return kDoubleOps * kDoubleRoundoff * magnitude(part, scale, ray, t);
  // Whether a float triangle is hit is decided in float, whatever precision the range gets
  // afterwards; in the plane, the ray's rounding moves the crossing point by that over cos.
  const double cosine = std::max(incidence(part, ray, t).cosine, 1e-300);
  return kFloatOps * kFloatRoundoff * magnitude(part, scale, ray, t) / cosine + pose_rounding(part, scale, ray, t, engine);
}

double pose_rounding(const Part& part, const PartScale& scale, const OracleRay& ray, double t, Engine engine) {
  if (engine != Engine::moving || part.kind != Kind::triangle) return 0.0;
  // The moving caster tests the mesh's float vertices in the object's frame, exactly; the oracle
  // (and the caster's double range) is given its world vertices, pose + R v rounded to double,
  // which lie up to ~u (|pose| + S) from them (docs/numerics.md "Error bounds"). Negligible
  // unless the object is far from the world's origin and small (a 1e-6 m mesh 1e6 m out:
  // 1e-10 m against 1e-12 m).
  const double cosine = std::max(incidence(part, ray, t).cosine, 1e-300);
  return 4.0 * kDoubleRoundoff * (norm(scale.reference) + scale.size_m) / cosine;
}

double float_normal_error(const Part& part, const OracleRay& ray, double t) {
  if (part.kind != Kind::triangle) return 0.0;
  const auto& v = part.vertices;
  const Vec ab = minus(v[1], v[0]), bc = minus(v[2], v[1]), ca = minus(v[0], v[2]);
  const double longest = std::sqrt(std::max({dot(ab, ab), dot(bc, bc), dot(ca, ca)}));
  const double twice_area = norm(cross(ab, minus(v[2], v[0])));
  if (!(twice_area > 0.0)) return std::numeric_limits<double>::infinity();
  const double cosine = std::max(incidence(part, ray, t).cosine, 1e-300);
  return 8.0 * kFloatRoundoff * longest * longest * longest / twice_area / cosine;
}

double order_bound(const Part& part, const PartScale& scale, const OracleRay& ray, double t, Engine engine) {
  if (part.kind != Kind::triangle) return range_bound(part, scale, ray, t, engine);
  const double cosine = std::max(incidence(part, ray, t).cosine, 1e-300);
  // Embree orders a triangle (against the reach its query gets, and the origin: tnear = 0) by
  // its float distance, whose normal loses digits to cancellation on a sliver (float_normal_error),
  // and which for the moving caster is that of the unrounded triangle: its double range may lie
  // pose_rounding further (docs/numerics.md).
  return kFloatOps * kFloatRoundoff * magnitude(part, scale, ray, t) / cosine + float_normal_error(part, ray, t) +
         pose_rounding(part, scale, ray, t, engine);
}

const char* fault_name(Fault fault) {
  switch (fault) {
    case Fault::none: return "none";
    case Fault::not_finite: return "not_finite";
    case Fault::wrong_object: return "wrong_object";
    case Fault::range: return "range";
    case Fault::missed: return "missed";
    case Fault::oracle_failed: return "oracle_failed";
  }
  return "?";
}

namespace {

// The part's answers once its boundary or the ray's origin moves by `delta` either way: what
// the caster may answer instead of the exact one when the ray is that close to an edge, a
// tangent or (its origin) to the surface. Ranges are measured from the true origin.
// `grow` moves the boundary, `shift` the origin (by the range bound: where the origin lies
// within it of the surface, whether the surface is ahead, behind or at 0 is not decided).
std::vector<PartAnswer> variants(const Part& part, const OracleRay& ray, double grow, double shift_m) {
  std::vector<PartAnswer> out;
  // A bound beyond any scene's size (a ray grazing at 1e-300) moves the origin 1e12 m at most.
  grow = std::min(grow, 1e12);
  shift_m = std::min(shift_m, 1e12);
  out.push_back(cast_part(part, ray, grow));
  out.push_back(cast_part(part, ray, -grow));
  const Vec d = unit(ray.direction);
  for (const double shift : {-shift_m, shift_m}) {
    OracleRay moved = ray;
    for (int i = 0; i < 3; ++i) moved.origin[i] += shift * d[i];
    PartAnswer a = cast_part(part, moved);
    a.range_m += shift;
    out.push_back(a);
  }
  return out;
}

std::string describe(const OracleRay& ray) {
  std::ostringstream s;
  s.precision(17);
  s << "origin (" << ray.origin[0] << ", " << ray.origin[1] << ", " << ray.origin[2] << ") direction (" << ray.direction[0]
    << ", " << ray.direction[1] << ", " << ray.direction[2] << ") reach " << ray.reach;
  return s.str();
}

}  // namespace

Verdict judge(std::span<const Part> parts, std::span<const PartScale> scales, const OracleRay& ray, std::uint32_t ignored,
              const CasterAnswer& answer, Engine engine) {
  Verdict v;
  std::ostringstream what;
  what.precision(17);
  const auto fail = [&](Fault fault) {
    v.fault = fault;
    v.what = what.str() + "; ray " + describe(ray);
    return v;
  };
  if (answer.hit && !(std::isfinite(answer.range_m) && answer.range_m > 0.0 && answer.range_m <= ray.reach)) {
    what << "range " << answer.range_m << " not in (0, reach]";
    return fail(Fault::not_finite);
  }
  try {
    std::vector<PartAnswer> exact(parts.size());
    for (std::size_t i = 0; i < parts.size(); ++i) {
      if (parts[i].object == ignored) continue;
      exact[i] = cast_part(parts[i], ray);
      // The filter's enclosure must be far narrower than the bound it is held against.
      if (exact[i].hit && exact[i].range_error_m > 0.05 * range_bound(parts[i], scales[i], ray, exact[i].range_m, engine)) {
        exact[i] = cast_part(parts[i], ray, 0.0, true);
      }
      v.exact = v.exact || exact[i].exact;
    }
    // 1. The caster's hit must be a part of that object, at its range within the bound (or at
    // the range one of its variants gives, if the ray is within the bound of a boundary).
    std::optional<std::size_t> found;
    double found_bound = 0.0;
    if (answer.hit) {
      double best_ratio = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < parts.size(); ++i) {
        if (parts[i].object != answer.object || !exact[i].hit) continue;
        const double error = std::abs(answer.range_m - exact[i].range_m - exact[i].range_tail_m);
        const double bound = range_bound(parts[i], scales[i], ray, exact[i].range_m, engine) + exact[i].range_error_m;
        if (error <= bound && error / bound < best_ratio) {
          best_ratio = error / bound;
          found = i;
          found_bound = bound;
          v.measured = true;
          v.kind = parts[i].kind;
          v.part = i;
          v.error_m = error;
          v.bound_m = bound;
          v.ulps = error / ulp(exact[i].range_m);
          v.cosine = incidence(parts[i], ray, exact[i].range_m).cosine;
        }
      }
      for (std::size_t i = 0; !found && i < parts.size(); ++i) {
        if (parts[i].object != answer.object) continue;
        const double t = answer.range_m;
        // A boundary moved by the tolerance moves the hit along the ray by that over the cosine.
        const double boundary = boundary_bound(parts[i], scales[i], ray, t, engine);
        const double bound = range_bound(parts[i], scales[i], ray, t, engine) +
                             boundary / std::max(incidence(parts[i], ray, t, 4.0 * boundary).cosine, 1e-300);
        for (const PartAnswer& a : variants(parts[i], ray, boundary, bound)) {
          if (a.hit && std::abs(t - a.range_m) <= bound + a.range_error_m) {
            found = i;
            found_bound = bound;
            v.excused = true;
            break;
          }
        }
      }
      // A plane the ray is parallel to within the rounding of the caster's n . d: the sign of
      // that product, so whether the plane lies ahead, is not decided, nor its range
      // (docs/numerics.md "Error bounds", planes): a range in (0, reach] may be answered, and
      // may hide what lies beyond it, but only one the rounded quotient can reach: the origin's
      // height over the plane (less its rounding) divided by at most kPlaneParallelCosine.
      for (std::size_t i = 0; !found && i < parts.size(); ++i) {
        if (parts[i].object != answer.object || parts[i].kind != Kind::plane) continue;
        const double height = std::abs(dot(parts[i].normal, ray.origin) - parts[i].offset) / norm(parts[i].normal);
        const double height_rounding = kDoubleOps * kDoubleRoundoff * magnitude(parts[i], scales[i], ray, 0.0);
        if (incidence(parts[i], ray, answer.range_m).cosine <= kPlaneParallelCosine &&
            answer.range_m * kPlaneParallelCosine >= height - height_rounding) {
          found = i;
          found_bound = ray.reach;
          v.excused = true;
        }
      }
      // A triangle's hit is decided on its float copy: accepted where the hit point lies within
      // the float boundary tolerance of the double triangle in space (slivers and degenerate
      // triangles, whose plane the rounding turns, are held to this only).
      for (std::size_t i = 0; !found && i < parts.size(); ++i) {
        if (parts[i].object != answer.object || parts[i].kind != Kind::triangle) continue;
        const Vec d = unit(ray.direction);
        const double t = answer.range_m;
        const Vec x{ray.origin[0] + t * d[0], ray.origin[1] + t * d[1], ray.origin[2] + t * d[2]};
        // Along the ray the hit may be off by the range bound (Embree's float distance at grazing
        // incidence), across it by the float rounding of the vertices and the ray.
        const double tolerance = kFloatOps * kFloatRoundoff * magnitude(parts[i], scales[i], ray, t) +
                                 range_bound(parts[i], scales[i], ray, t, engine);
        if (triangle_distance(x, parts[i].vertices) <= tolerance) {
          found = i;
          found_bound = range_bound(parts[i], scales[i], ray, t, engine);
          v.excused = true;
        }
      }
      if (!found) {
        bool object_hit = false;
        for (std::size_t i = 0; i < parts.size(); ++i) {
          if (parts[i].object == answer.object && exact[i].hit) {
            object_hit = true;
            what << "object " << answer.object << " (" << kind_name(parts[i].kind) << ") at " << answer.range_m
                 << ", exact " << exact_range_text(parts[i], ray) << ", bound "
                 << range_bound(parts[i], scales[i], ray, exact[i].range_m, engine) << "; ";
          }
        }
        if (!object_hit) what << "object " << answer.object << " hit at " << answer.range_m << " but the oracle misses it";
        return fail(object_hit ? Fault::range : Fault::wrong_object);
      }
    }
    // 2. No part nearer than the caster's answer (beyond the bounds of both) may be skipped,
    // unless the ray is within the bound of its boundary or the reach.
    for (std::size_t i = 0; i < parts.size(); ++i) {
      if (parts[i].object == ignored || !exact[i].hit || (found && i == *found)) continue;
      const double t = exact[i].range_m;
      // Embree (and ODE) order triangles against other surfaces by float distances: a triangle
      // within its order bound of the answer may lose to it.
      const double bound = order_bound(parts[i], scales[i], ray, t, engine);
      // Whether a triangle is hit at all, also near the origin and the reach, is decided in
      // Embree's (or ODE's) float arithmetic: its boundary bound applies there.
      const double decided = std::max(bound, boundary_bound(parts[i], scales[i], ray, t, engine));
      if (t > ray.reach + decided) continue;
      // Two triangles of one moving mesh are ordered by the float distances of both unrounded
      // triangles: the answer's own rounding counts too.
      const double found_rounding = found && parts[*found].object == parts[i].object
                                        ? pose_rounding(parts[*found], scales[*found], ray, answer.range_m, engine)
                                        : 0.0;
      // Behind, or a tie within the bounds.
      if (answer.hit && t >= answer.range_m - bound - found_bound - found_rounding) continue;
      if (t >= ray.reach - decided) continue;  // at the reach within the bound
      if (t <= decided) continue;  // at the origin within the bound: a range of 0 is no hit
      const double limit = answer.hit ? answer.range_m - found_bound : ray.reach;
      bool excused = false;
      const auto answers = variants(parts[i], ray, boundary_bound(parts[i], scales[i], ray, t, engine), bound);
      for (const PartAnswer& a : answers) {
        if (!a.hit || a.range_m + bound >= limit) excused = true;
      }
      // The origin within the tolerance of a solid's surface (inside the grown solid, not the
      // shrunk one): the caster may take it as on the surface, where a range of 0 is no hit.
      if (answers[0].origin_inside != answers[1].origin_inside) excused = true;
      if (excused) {
        v.excused = true;
        continue;
      }
      what << "skipped object " << parts[i].object << " (" << kind_name(parts[i].kind) << ", part " << i << ") exact "
           << exact_range_text(parts[i], ray) << " bound " << bound << "; caster "
           << (answer.hit ? "hit object " + std::to_string(answer.object) + " at " : std::string("missed"));
      if (answer.hit) what << answer.range_m;
      return fail(!answer.hit ? Fault::missed : parts[i].object == answer.object ? Fault::range : Fault::wrong_object);
    }
  } catch (const std::domain_error& e) {
    what << e.what();
    return fail(Fault::oracle_failed);
  }
  return v;
}

}  // namespace ldoem::oracle
