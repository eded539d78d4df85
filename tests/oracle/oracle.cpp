// The oracle's arithmetic: one generic solver over a number type, run first on CGAL's intervals
// (a floating filter: rigorous enclosures, every comparison either certain or an exception) and,
// when an interval comparison is uncertain, again on CORE::Expr (CGAL's exact kernel with
// square roots), whose comparisons are always decided exactly. All rays are written in the
// parameter l of origin + l * direction; the range is l * |direction| (one square root), so no
// division by |direction| ever enters a comparison.
#include "oracle.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel_with_sqrt.h>
#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace ldoem::oracle {
namespace {

using Exact = CGAL::Exact_predicates_exact_constructions_kernel_with_sqrt::FT;
using Interval = CGAL::Interval_nt<false>;  // needs the rounding mode set upwards (FilterScope)

template <class NT>
struct V {
  NT x, y, z;
};
template <class NT>
V<NT> make(const Vec& v) {
  return {NT(v[0]), NT(v[1]), NT(v[2])};
}
template <class NT>
V<NT> operator-(const V<NT>& a, const V<NT>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class NT>
NT dot(const V<NT>& a, const V<NT>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class NT>
V<NT> cross(const V<NT>& a, const V<NT>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// A parameter interval [enter, leave] along the ray; an end may be unbounded.
template <class NT>
struct ParamSpan {
  bool empty = false;
  std::optional<NT> enter, leave;  // nothing: unbounded
};
template <class NT>
ParamSpan<NT> empty_span() {
  ParamSpan<NT> span;
  span.empty = true;
  return span;
}

template <class NT>
void clip_slab(ParamSpan<NT>& span, const NT& start, const NT& velocity, const NT& half) {
  if (span.empty) return;
  if (velocity == NT(0)) {
    if (start > half || start < -half) span.empty = true;
    return;
  }
  NT near = (-half - start) / velocity, far = (half - start) / velocity;
  if (velocity < NT(0)) std::swap(near, far);
  if (!span.enter || near > *span.enter) span.enter = near;
  if (!span.leave || far < *span.leave) span.leave = far;
  if (*span.enter > *span.leave) span.empty = true;
}

// Where |s + l v - centre_z e_z| <= r (a ball about (0, 0, centre_z)).
template <class NT>
ParamSpan<NT> ball(const V<NT>& s, const V<NT>& v, const NT& centre_z, const NT& r) {
  const V<NT> w{s.x, s.y, s.z - centre_z};
  const NT a = dot(v, v), b = dot(w, v), c = dot(w, w) - r * r;
  const NT disc = b * b - a * c;
  ParamSpan<NT> span;
  if (disc < NT(0)) return empty_span<NT>();
  const NT root = CGAL::sqrt(disc);
  span.enter = (-b - root) / a;
  span.leave = (-b + root) / a;
  return span;
}

// Where u_x^2 + u_y^2 <= r^2.
template <class NT>
ParamSpan<NT> infinite_cylinder(const V<NT>& s, const V<NT>& v, const NT& r) {
  const NT a = v.x * v.x + v.y * v.y;
  const NT c = s.x * s.x + s.y * s.y - r * r;
  if (a == NT(0)) return c > NT(0) ? empty_span<NT>() : ParamSpan<NT>{};
  const NT b = s.x * v.x + s.y * v.y;
  const NT disc = b * b - a * c;
  if (disc < NT(0)) return empty_span<NT>();
  const NT root = CGAL::sqrt(disc);
  ParamSpan<NT> span;
  span.enter = (-b - root) / a;
  span.leave = (-b + root) / a;
  return span;
}

template <class NT>
struct Solution {
  bool hit = false;
  NT l{};  // origin + l * direction
  bool boundary = false;
  bool inside = false;  // the origin is strictly inside the solid
};

// The caster's rule for a solid: the entry if at or ahead of the origin, else the exit; a
// surface at l = 0 is no hit.
template <class NT>
Solution<NT> from_span(ParamSpan<NT> span) {
  if (span.empty || !span.enter || !span.leave) return {};
  if (*span.enter > *span.leave) return {};
  Solution<NT> out;
  out.boundary = *span.enter == *span.leave;
  out.inside = *span.enter < NT(0) && *span.leave > NT(0);
  out.l = *span.enter >= NT(0) ? *span.enter : *span.leave;
  out.hit = out.l > NT(0);
  return out;
}

template <class NT>
Solution<NT> solve(const Part& part, const OracleRay& ray, double grow_m) {
  const V<NT> o = make<NT>(ray.origin), d = make<NT>(ray.direction);
  const NT grow(grow_m);
  if (part.kind == Kind::plane) {
    const V<NT> n = make<NT>(part.normal);
    const NT along = dot(n, d);
    if (along == NT(0)) return {};
    Solution<NT> out;
    out.l = (NT(part.offset) - dot(n, o)) / along;
    out.hit = out.l > NT(0);
    return out;
  }
  if (part.kind == Kind::triangle) {
    const V<NT> a = make<NT>(part.vertices[0]), b = make<NT>(part.vertices[1]), c = make<NT>(part.vertices[2]);
    const V<NT> e1 = b - a, e2 = c - a;
    const V<NT> p = cross(d, e2);
    const NT det = dot(e1, p);
    if (det == NT(0)) return {};  // parallel to the plane, or a degenerate triangle
    const V<NT> t = o - a;
    const V<NT> q = cross(t, e1);
    // Barycentric weights times det: of b, of c, of a. The point's distance from the edge
    // opposite a vertex is weight * |n| / |that edge|, so growing by g asks
    // weight * |n| + g * |edge| * det-sign >= 0 (both sides scaled by |det|).
    const NT wb = dot(t, p), wc = dot(d, q), wa = det - wb - wc;
    const NT sign = det > NT(0) ? NT(1) : NT(-1);
    Solution<NT> out;
    if (grow_m == 0.0) {
      if (sign * wa < NT(0) || sign * wb < NT(0) || sign * wc < NT(0)) return {};
      out.boundary = wa == NT(0) || wb == NT(0) || wc == NT(0);
    } else {
      const V<NT> n = cross(e1, e2);
      const NT area2 = CGAL::sqrt(dot(n, n));
      const V<NT> bc = c - b;
      const NT scale = CGAL::abs(det) / area2;  // |det| / |n|: turns edge lengths into weights
      if (sign * wa + grow * scale * CGAL::sqrt(dot(bc, bc)) < NT(0)) return {};
      if (sign * wb + grow * scale * CGAL::sqrt(dot(e2, e2)) < NT(0)) return {};
      if (sign * wc + grow * scale * CGAL::sqrt(dot(e1, e1)) < NT(0)) return {};
    }
    out.l = dot(e2, q) / det;
    out.hit = out.l > NT(0);
    return out;
  }
  // Primitives: the ray in the local frame u = R^T (p - centre).
  const auto& r = part.rotation;
  const V<NT> w = o - make<NT>(part.centre);
  const auto local = [&](const V<NT>& x) {
    return V<NT>{NT(r[0]) * x.x + NT(r[3]) * x.y + NT(r[6]) * x.z, NT(r[1]) * x.x + NT(r[4]) * x.y + NT(r[7]) * x.z,
                 NT(r[2]) * x.x + NT(r[5]) * x.y + NT(r[8]) * x.z};
  };
  const V<NT> s = local(w), v = local(d);
  const NT radius = NT(part.radius) + grow;
  switch (part.kind) {
    case Kind::box: {
      ParamSpan<NT> span;
      const NT half[3] = {NT(part.half[0]) + grow, NT(part.half[1]) + grow, NT(part.half[2]) + grow};
      if (half[0] < NT(0) || half[1] < NT(0) || half[2] < NT(0)) return {};
      clip_slab(span, s.x, v.x, half[0]);
      clip_slab(span, s.y, v.y, half[1]);
      clip_slab(span, s.z, v.z, half[2]);
      return from_span(span);
    }
    case Kind::sphere:
      if (radius < NT(0)) return {};
      return from_span(ball(s, v, NT(0), radius));
    case Kind::cylinder: {
      const NT half = NT(part.half_length) + grow;
      if (radius < NT(0) || half < NT(0)) return {};
      ParamSpan<NT> span = infinite_cylinder(s, v, radius);
      clip_slab(span, s.z, v.z, half);
      return from_span(span);
    }
    case Kind::capsule: {
      if (radius < NT(0)) return {};
      const NT half(part.half_length);
      // Convex, the union of its cylinder and end balls: one interval, the hull of the parts'.
      ParamSpan<NT> hull = empty_span<NT>();
      ParamSpan<NT> pieces[3] = {infinite_cylinder(s, v, radius), ball(s, v, -half, radius), ball(s, v, half, radius)};
      clip_slab(pieces[0], s.z, v.z, half);
      for (const ParamSpan<NT>& piece : pieces) {
        if (piece.empty || !piece.enter || !piece.leave) continue;
        if (hull.empty) {
          hull = piece;
          continue;
        }
        if (*piece.enter < *hull.enter) hull.enter = piece.enter;
        if (*piece.leave > *hull.leave) hull.leave = piece.leave;
      }
      return from_span(hull);
    }
    default:
      return {};
  }
}

// Sets the rounding mode Interval needs and restores the caller's.
struct FilterScope {
  CGAL::Protect_FPU_rounding<true> guard;
};

PartAnswer interval_answer(const Part& part, const OracleRay& ray, double grow_m) {
  FilterScope scope;
  const Solution<Interval> s = solve<Interval>(part, ray, grow_m);
  PartAnswer out;
  out.origin_inside = s.inside;
  if (!s.hit) return out;
  const V<Interval> d = make<Interval>(ray.direction);
  const Interval range = s.l * CGAL::sqrt(dot(d, d));
  out.hit = true;
  out.boundary = s.boundary;
  out.range_m = 0.5 * range.inf() + 0.5 * range.sup();
  out.range_error_m = std::max(range.sup() - out.range_m, out.range_m - range.inf());
  if (!std::isfinite(out.range_error_m)) throw CGAL::Uncertain_conversion_exception("unbounded interval");
  return out;
}

Exact exact_range(const Solution<Exact>& s, const OracleRay& ray) {
  const V<Exact> d = make<Exact>(ray.direction);
  return s.l * CGAL::sqrt(dot(d, d));
}

PartAnswer exact_answer(const Part& part, const OracleRay& ray, double grow_m) {
  const Solution<Exact> s = solve<Exact>(part, ray, grow_m);
  PartAnswer out;
  out.exact = true;
  out.origin_inside = s.inside;
  if (!s.hit) return out;
  const Exact range = exact_range(s, ray);
  out.hit = true;
  out.boundary = s.boundary;
  out.range_m = CGAL::to_double(range);
  if (!std::isfinite(out.range_m)) return PartAnswer{};  // beyond any double, so beyond any reach
  const Exact tail = range - Exact(out.range_m);
  out.range_tail_m = CGAL::to_double(tail);
  out.range_error_m = 4.0 * std::numeric_limits<double>::epsilon() * std::abs(out.range_tail_m);
  return out;
}

Answer exact_scene(std::span<const Part> parts, const OracleRay& ray, std::uint32_t ignored);

}  // namespace

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::plane: return "plane";
    case Kind::box: return "box";
    case Kind::sphere: return "sphere";
    case Kind::cylinder: return "cylinder";
    case Kind::capsule: return "capsule";
    case Kind::triangle: return "triangle";
  }
  return "?";
}

PartAnswer cast_part(const Part& part, const OracleRay& ray, double grow_m, bool exact) {
  // Exact numbers of infinities do not exist (CORE aborts on them).
  const auto finite = [](const auto& values) { return std::all_of(values.begin(), values.end(), [](double x) { return std::isfinite(x); }); };
  if (!std::isfinite(grow_m) || !finite(ray.origin) || !finite(ray.direction) || !finite(part.centre) || !finite(part.rotation) ||
      !finite(part.half) || !finite(part.normal) || !finite(part.vertices[0]) || !finite(part.vertices[1]) ||
      !finite(part.vertices[2]) || !std::isfinite(part.radius) || !std::isfinite(part.half_length) || !std::isfinite(part.offset)) {
    throw std::domain_error("oracle: an input is not finite");
  }
  if (!exact) {
    try {
      return interval_answer(part, ray, grow_m);
    } catch (const CGAL::Uncertain_conversion_exception&) {
      // The filter could not decide: the exact numbers below always can.
    }
  }
  try {
    return exact_answer(part, ray, grow_m);
  } catch (const CGAL::Failure_exception& e) {
    throw std::domain_error(std::string("oracle: CORE::Expr failed: ") + e.what());
  }
}

Answer cast(std::span<const Part> parts, const OracleRay& ray, std::uint32_t ignored) {
  // The filter answers each part; only when two hits or a hit and the reach cannot be told
  // apart by their enclosures is the whole scene decided again exactly.
  Answer best;
  bool need_exact = false;
  std::vector<PartAnswer> answers(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].object == ignored) continue;
    answers[i] = cast_part(parts[i], ray);
    if (answers[i].exact) need_exact = true;
  }
  const auto lower = [](const PartAnswer& a) { return a.range_m - a.range_error_m; };
  const auto upper = [](const PartAnswer& a) { return a.range_m + a.range_error_m; };
  for (std::size_t i = 0; i < parts.size() && !need_exact; ++i) {
    if (!answers[i].hit) continue;
    if (!(upper(answers[i]) < ray.reach || lower(answers[i]) > ray.reach)) need_exact = true;
    for (std::size_t j = 0; j < i; ++j) {
      if (answers[j].hit && parts[j].object != parts[i].object && !(upper(answers[i]) < lower(answers[j]) || upper(answers[j]) < lower(answers[i]))) {
        need_exact = true;
      }
    }
  }
  if (!need_exact) {
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const PartAnswer& a = answers[i];
      if (!a.hit || a.range_m > ray.reach) continue;
      if (!best.hit || a.range_m < best.range_m || (a.range_m == best.range_m && parts[i].object < best.object)) {
        best = Answer{true, parts[i].object, i, a.range_m, 0.0, false, a.boundary, false, false};
      }
    }
    return best;
  }
  try {
    return exact_scene(parts, ray, ignored);
  } catch (const CGAL::Failure_exception& e) {
    throw std::domain_error(std::string("oracle: CORE::Expr failed: ") + e.what());
  }
}

namespace {

Answer exact_scene(std::span<const Part> parts, const OracleRay& ray, std::uint32_t ignored) {
  Answer best;
  std::optional<Exact> best_exact;
  best.exact = true;
  const Exact reach(ray.reach);
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].object == ignored) continue;
    const Solution<Exact> s = solve<Exact>(parts[i], ray, 0.0);
    if (!s.hit) continue;
    const Exact range = exact_range(s, ray);
    if (range > reach) continue;  // (also every range beyond the doubles)
    const bool nearer = !best.hit || range < *best_exact;
    const bool same = best.hit && range == *best_exact;
    if (same && parts[i].object != best.object) best.tie = true;
    if (nearer || (same && parts[i].object < best.object)) {
      if (nearer) best.tie = false;
      best.hit = true;
      best.object = parts[i].object;
      best.part = i;
      best.tangent = s.boundary;
      best_exact = range;
    }
  }
  if (best.hit) {
    best.range_m = CGAL::to_double(*best_exact);
    best.range_tail_m = CGAL::to_double(*best_exact - Exact(best.range_m));
    best.at_reach = *best_exact == reach;
  }
  return best;
}

}  // namespace

std::string exact_range_text(const Part& part, const OracleRay& ray, int digits) {
  const Solution<Exact> s = solve<Exact>(part, ray, 0.0);
  if (!s.hit) return "miss";
  const Exact range = exact_range(s, ray);
  if (!std::isfinite(CGAL::to_double(range))) return "beyond the doubles";
  // Two doubles give ~32 digits; more come from subtracting them off exactly.
  std::ostringstream out;
  out.precision(17);
  Exact rest = range;
  out << "[";
  for (int k = 0; k < (digits + 15) / 16; ++k) {
    const double piece = CGAL::to_double(rest);
    out << (k ? " + " : "") << piece;
    rest = rest - Exact(piece);
  }
  out << "]";
  return out.str();
}

}  // namespace ldoem::oracle
