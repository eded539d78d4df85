#include "ldoem/raycast/embree_ray_caster.hpp"

#include "embree_device.hpp"
#include "exact_primitives.hpp"
#include "ray_probe.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ldoem::raycast {
namespace {

using detail::round_down_to_float;
using detail::round_up_to_float;
using detail::to_float;

// Embree traverses a float copy of the double ray; its boxes are padded by this fraction of the
// scene's size so that rounding of the ray (origin and direction, ~1e-7 relative) never drops a
// candidate whose exact ODE test would hit. Padding costs a few extra exact tests, nothing more.
constexpr double kBoundsPaddingFraction = 1e-5;

struct Bounds {
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d upper = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  void extend(const Eigen::Vector3d& p) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  bool empty() const { return !(lower.x() <= upper.x()); }
};

// Per-cast state handed to the user-geometry callback: Embree's context must come first.
struct CastContext {
  RTCIntersectContext embree;
  const detail::CheckedRay* ray = nullptr;
  std::optional<detail::Contact> best;
  unsigned ignored_primitive = RTC_INVALID_GEOMETRY_ID;  // the Embree primID of Ray::ignored_object
  Eigen::Vector3d local_origin;  // the ray's origin in Embree's (re-centred) frame, in double
  // Embree's float ray starts this far along the double one (near the geometry): its distances
  // are ranges minus this.
  double skip_m = 0.0;
  // The nearest triangle the filter accepted, by its double-precision range (Embree's own
  // record orders by float distances, and a primitive accepted later overwrites it).
  double triangle_range_m = std::numeric_limits<double>::infinity();
  unsigned triangle_geom_id = RTC_INVALID_GEOMETRY_ID;
  unsigned triangle_prim_id = RTC_INVALID_GEOMETRY_ID;
};

struct PrimitiveSet {
  std::vector<std::size_t> object_indices;  // Embree primID -> Scene::objects index
  std::vector<detail::ExactPrimitive> shapes;  // Embree primID -> what the exact test needs
  std::vector<RTCBounds> bounds;            // local (re-centred) float frame
};

// The plane of one triangle in double precision: the unit normal n of (b - a) x (c - a) (zero
// for a degenerate triangle), normalised once here rather than on every hit, and its offset
// n . (a - frame origin) in Embree's re-centred frame. Kept per triangle so that a hit reads one
// record rather than an index triple and three vertices from cold memory (that was ~20 % of a
// cast on a 100k-triangle mesh); 32 bytes aligned, so a record is one cache line, never two.
struct alignas(32) TrianglePlane {
  Eigen::Vector3d normal;
  double offset_m;
};

struct MeshRecord {
  std::size_t object_index;
  std::vector<Eigen::Vector3d> world_vertices_m;  // while building; released afterwards
  std::vector<std::array<std::uint32_t, 3>> triangles;  // idem
  std::vector<TrianglePlane> planes;  // Embree primID -> plane, for the double-precision range
};

void primitive_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* set = static_cast<const PrimitiveSet*>(args->geometryUserPtr);
  *args->bounds_o = set->bounds[args->primID];
}

void primitive_intersect(const RTCIntersectFunctionNArguments* args) {
  if (args->N != 1 || args->valid[0] == 0) return;  // only rtcIntersect1 is used
  auto* context = reinterpret_cast<CastContext*>(args->context);
  if (args->primID == context->ignored_primitive) return;
  const auto* set = static_cast<const PrimitiveSet*>(args->geometryUserPtr);
  const auto hit = detail::intersect(set->shapes[args->primID], *context->ray);
  if (!hit || (context->best && !detail::nearer(*hit, *context->best))) return;
  auto* rayhit = reinterpret_cast<RTCRayHit*>(args->rayhit);
  // Meshes may already have shortened tfar; a primitive behind that triangle loses.
  if (hit->range_m > static_cast<double>(rayhit->ray.tfar) + context->skip_m) return;
  context->best = hit;
  rayhit->ray.tfar = round_up_to_float(std::max(hit->range_m - context->skip_m, 0.0));
  rayhit->hit.geomID = args->geomID;
  rayhit->hit.primID = args->primID;
  rayhit->hit.Ng_x = static_cast<float>(hit->normal.x());
  rayhit->hit.Ng_y = static_cast<float>(hit->normal.y());
  rayhit->hit.Ng_z = static_cast<float>(hit->normal.z());
  rayhit->hit.u = 0.0f;
  rayhit->hit.v = 0.0f;
  rayhit->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

// The range of a hit on a triangle: from the triangle's double-precision plane, unless the ray
// grazes that plane (|n . d| <= 1e-6: zero for a degenerate triangle), then Embree's float
// distance. Embree's float distance is exact only to ~1e-7 relative.
double triangle_range(const TrianglePlane& plane, const Eigen::Vector3d& local_origin, const Eigen::Vector3d& direction,
                      double embree_t) {
  const double denominator = plane.normal.dot(direction);
  if (std::abs(denominator) > 1e-6) {
    const double exact_m = (plane.offset_m - plane.normal.dot(local_origin)) / denominator;
    if (std::isfinite(exact_m)) return exact_m;
  }
  return embree_t;
}

// Called by Embree for each triangle the ray meets while it is still traversing. Embree accepts
// float distances >= tnear = 0; a triangle whose range in double is not in (0, reach] (the ray
// leaves its surface, issue 26) is refused here, so that it does not shorten the ray (a tfar of
// 0 hid everything else) and Embree goes on to the next candidate.
// Triangles are ordered here by their double ranges, not by Embree's float distances: on a
// sliver (a triangle much narrower than long) Embree's float normal loses most of its digits to
// cancellation and its distance can be off by hundreds of float ulps (1.1e-10 m at 3.2e-6 m,
// docs/numerics.md "Findings" 10), which let a farther sliver win. The accepted triangle's tfar
// becomes its double range rounded up (Embree lets a filter set tfar), so a triangle is only
// lost when its own float distance lies beyond the nearest double range found so far, or below
// tnear = 0 (the judge's order bound, "Findings" 11).
void accept_triangle_ahead(const RTCFilterFunctionNArguments* args) {
  const auto* planes = static_cast<const TrianglePlane*>(args->geometryUserPtr);
  auto* context = reinterpret_cast<CastContext*>(args->context);
  const unsigned prim_id = RTCHitN_primID(args->hit, args->N, 0);
  const TrianglePlane& plane = planes[prim_id];
  float& tfar = RTCRayN_tfar(args->ray, args->N, 0);
  const double range_m = triangle_range(plane, context->local_origin, context->ray->direction, tfar + context->skip_m);
  // Not nearer than a triangle accepted before: coincident triangles keep the first found.
  if (!(range_m > 0.0) || range_m > context->ray->max_range_m || !(range_m < context->triangle_range_m)) {
    args->valid[0] = 0;
    return;
  }
  context->triangle_range_m = range_m;
  context->triangle_geom_id = RTCHitN_geomID(args->hit, args->N, 0);
  context->triangle_prim_id = prim_id;
  // Never beyond a plane or primitive found nearer (the cast keeps it in the end anyway).
  const double nearest_m = context->best ? std::min(range_m, context->best->range_m) : range_m;
  tfar = round_up_to_float(std::max(nearest_m - context->skip_m, 0.0));
}

void primitive_occluded(const RTCOccludedFunctionNArguments* args) {
  // Not used (we only ask for nearest hits); answering "not occluded" keeps Embree defined.
  (void)args;
}

}  // namespace

struct EmbreeRayCaster::Impl {
  const OdeWorld& world;
  std::string device_error;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  Eigen::Vector3d frame_origin_m = Eigen::Vector3d::Zero();  // Embree coordinates are relative to this
  std::vector<detail::ExactPlane> planes;
  PrimitiveSet primitives;
  unsigned primitive_geom_id = RTC_INVALID_GEOMETRY_ID;
  std::vector<MeshRecord> meshes;
  std::vector<int> mesh_by_geom_id;  // Embree geomID -> index in meshes, or -1
  std::vector<unsigned> primitive_by_object;  // Scene::objects index -> primID (invalid: not a primitive)
  // Every float box and vertex Embree holds, in its (local) frame: a ray that misses this box
  // needs no Embree call.
  Bounds embree_bounds;
  double embree_extent_m = 0.0;  // the largest |coordinate| of embree_bounds
  Eigen::Vector3d embree_centre_m = Eigen::Vector3d::Zero();     // of embree_bounds
  Eigen::Vector3d embree_half_size_m = Eigen::Vector3d::Zero();  // idem
  double embree_radius_m = 0.0;  // of the sphere about embree_centre_m holding embree_bounds

  explicit Impl(const OdeWorld& w) : world(w) {}
  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }

  void build();
  Bounds collect_geometry();
  void attach_primitives(const std::vector<Bounds>& world_bounds, double padding_m);
  void attach_mesh(MeshRecord& mesh);
  Hit mesh_hit(const detail::CheckedRay& ray, const CastContext& context) const;
  bool may_meet_embree_geometry(const Eigen::Vector3d& local_origin, const Eigen::Vector3d& direction,
                                double reach_m) const;
};

Bounds EmbreeRayCaster::Impl::collect_geometry() {
  Bounds scene_bounds;
  for (std::size_t i = 0; i < world.object_count(); ++i) {
    if (world.is_plane(i)) {
      planes.push_back(detail::exact_plane_of(world, i));
      continue;
    }
    if (world.is_mesh(i)) {
      const auto& object = world.object(i);
      const auto& mesh = std::get<scene::Mesh>(object.shape);
      MeshRecord record{i, {}, mesh.triangles, {}};
      record.world_vertices_m.reserve(mesh.vertices_m.size());
      for (const Eigen::Vector3f& v : mesh.vertices_m) {
        const Eigen::Vector3d p = object.pose.position_m + object.pose.orientation * v.cast<double>();
        record.world_vertices_m.push_back(p);
        scene_bounds.extend(p);
      }
      meshes.push_back(std::move(record));
      continue;
    }
    dReal aabb[6];
    dGeomGetAABB(world.geom(i), aabb);
    scene_bounds.extend(Eigen::Vector3d(aabb[0], aabb[2], aabb[4]));
    scene_bounds.extend(Eigen::Vector3d(aabb[1], aabb[3], aabb[5]));
    if (primitive_by_object.size() <= i) primitive_by_object.resize(i + 1, RTC_INVALID_GEOMETRY_ID);
    primitive_by_object[i] = static_cast<unsigned>(primitives.object_indices.size());
    primitives.object_indices.push_back(i);
    primitives.shapes.push_back(detail::exact_primitive_of(world, i));
  }
  return scene_bounds;
}

void EmbreeRayCaster::Impl::attach_primitives(const std::vector<Bounds>& world_bounds, double padding_m) {
  for (const Bounds& b : world_bounds) {
    const Eigen::Vector3d lower = b.lower - frame_origin_m - Eigen::Vector3d::Constant(padding_m);
    const Eigen::Vector3d upper = b.upper - frame_origin_m + Eigen::Vector3d::Constant(padding_m);
    RTCBounds box{};
    box.lower_x = round_down_to_float(lower.x());
    box.lower_y = round_down_to_float(lower.y());
    box.lower_z = round_down_to_float(lower.z());
    box.upper_x = round_up_to_float(upper.x());
    box.upper_y = round_up_to_float(upper.y());
    box.upper_z = round_up_to_float(upper.z());
    primitives.bounds.push_back(box);
    embree_bounds.extend(Eigen::Vector3d(box.lower_x, box.lower_y, box.lower_z));
    embree_bounds.extend(Eigen::Vector3d(box.upper_x, box.upper_y, box.upper_z));
  }
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(primitives.object_indices.size()));
  rtcSetGeometryUserData(geometry, &primitives);
  rtcSetGeometryBoundsFunction(geometry, primitive_bounds, nullptr);
  rtcSetGeometryIntersectFunction(geometry, primitive_intersect);
  rtcSetGeometryOccludedFunction(geometry, primitive_occluded);
  rtcCommitGeometry(geometry);
  primitive_geom_id = rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
}

void EmbreeRayCaster::Impl::attach_mesh(MeshRecord& mesh) {
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.world_vertices_m.size()));
  for (std::size_t v = 0; v < mesh.world_vertices_m.size(); ++v) {
    const Eigen::Vector3d local = mesh.world_vertices_m[v] - frame_origin_m;
    vertices[3 * v + 0] = to_float(local.x());
    vertices[3 * v + 1] = to_float(local.y());
    vertices[3 * v + 2] = to_float(local.z());
    embree_bounds.extend(Eigen::Vector3d(vertices[3 * v + 0], vertices[3 * v + 1], vertices[3 * v + 2]));
  }
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
  mesh.planes.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& triangle = mesh.triangles[t];
    for (std::size_t k = 0; k < 3; ++k) indices[3 * t + k] = triangle[k];
    const Eigen::Vector3d& a = mesh.world_vertices_m[triangle[0]];
    // Accurate to within an ulp per component, as the moving caster's (a sliver's plain cross
    // product put a grazing ray's crossing 3.4e-4 m ahead of where it is, "Findings" 12). The
    // edges are exact differences for vertices within a factor 2 of each other (Sterbenz).
    const Eigen::Vector3d normal =
        detail::accurate_cross(mesh.world_vertices_m[triangle[1]] - a, mesh.world_vertices_m[triangle[2]] - a);
    const double length = normal.norm();
    const Eigen::Vector3d unit = length > 0.0 && std::isfinite(length) ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero();
    mesh.planes.push_back({unit, unit.dot(a - frame_origin_m)});
  }
  mesh.world_vertices_m = {};
  mesh.triangles = {};
  rtcSetGeometryUserData(geometry, mesh.planes.data());
  rtcSetGeometryIntersectFilterFunction(geometry, accept_triangle_ahead);
  rtcCommitGeometry(geometry);
  const unsigned geom_id = rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  if (mesh_by_geom_id.size() <= geom_id) mesh_by_geom_id.resize(geom_id + 1, -1);
  mesh_by_geom_id[geom_id] = static_cast<int>(&mesh - meshes.data());
}

void EmbreeRayCaster::Impl::build() {
  device = detail::new_embree_device(nullptr, device_error);
  scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);

  const Bounds scene_bounds = collect_geometry();
  double padding_m = kBoundsPaddingFraction;
  if (!scene_bounds.empty()) {
    frame_origin_m = 0.5 * (scene_bounds.lower + scene_bounds.upper);
    const double half_extent_m = (0.5 * (scene_bounds.upper - scene_bounds.lower)).cwiseAbs().maxCoeff();
    padding_m = kBoundsPaddingFraction * std::max(1.0, half_extent_m);
  }
  if (!primitives.object_indices.empty()) {
    std::vector<Bounds> world_bounds;
    for (std::size_t i : primitives.object_indices) {
      dReal aabb[6];
      dGeomGetAABB(world.geom(i), aabb);
      Bounds b;
      b.extend(Eigen::Vector3d(aabb[0], aabb[2], aabb[4]));
      b.extend(Eigen::Vector3d(aabb[1], aabb[3], aabb[5]));
      world_bounds.push_back(b);
    }
    attach_primitives(world_bounds, padding_m);
  }
  for (MeshRecord& mesh : meshes) attach_mesh(mesh);
  if (!embree_bounds.empty()) {
    embree_extent_m = embree_bounds.lower.cwiseAbs().cwiseMax(embree_bounds.upper.cwiseAbs()).maxCoeff();
    embree_centre_m = 0.5 * (embree_bounds.lower + embree_bounds.upper);
    embree_half_size_m = 0.5 * (embree_bounds.upper - embree_bounds.lower);
    embree_radius_m = embree_half_size_m.norm();
  }
  rtcCommitScene(scene);
  if (!device_error.empty()) throw std::runtime_error(device_error);
}

// The nearest triangle the filter accepted (its range in (0, reach] already checked there).
Hit EmbreeRayCaster::Impl::mesh_hit(const detail::CheckedRay& ray, const CastContext& context) const {
  const MeshRecord& mesh = meshes[static_cast<std::size_t>(mesh_by_geom_id[context.triangle_geom_id])];
  const Eigen::Vector3d& normal = mesh.planes[context.triangle_prim_id].normal;
  return Hit{context.triangle_range_m, detail::facing_normal(normal, ray.direction),
             scene::optical_reflectance(world.object(mesh.object_index)), static_cast<std::uint32_t>(mesh.object_index)};
}

// Conservative: false only if Embree's float copy of the ray, up to `reach_m`, surely misses
// every box and triangle Embree holds, so that skipping rtcIntersect1 changes no answer. That
// copy deviates from the double ray by at most 2^-24 (|origin| + reach) per coordinate, and
// Embree's robust traversal widens its boxes by a few float ulps; the margin covers both, and
// this test's own rounding, many times over (1e-6 relative) and is still far below any
// object's size. Most rays of a scan point where no primitive or mesh is (a scanner sees a few
// objects and much floor and sky): for them this replaces Embree's call, setup and root node.
bool EmbreeRayCaster::Impl::may_meet_embree_geometry(const Eigen::Vector3d& local_origin, const Eigen::Vector3d& direction,
                                                     double reach_m) const {
  const Eigen::Vector3d& o = local_origin;
  const Eigen::Vector3d& box_lower = embree_bounds.lower;
  const Eigen::Vector3d& box_upper = embree_bounds.upper;
  // Starting among the objects (a scanner inside a room or a ring of objects): no test needed.
  if (o.x() >= box_lower.x() && o.x() <= box_upper.x() && o.y() >= box_lower.y() && o.y() <= box_upper.y() &&
      o.z() >= box_lower.z() && o.z() <= box_upper.z()) {
    return true;
  }
  constexpr double kRelativeMargin = 1e-6;
  const double margin_m =
      kRelativeMargin * (std::max({std::abs(o.x()), std::abs(o.y()), std::abs(o.z())}) + reach_m + embree_extent_m);
  // Separating axes of a segment and a box (no division): the box's three axes, then the
  // segment's direction crossed with each of them. m: segment centre from box centre; h: half
  // the segment; e: the box's half sizes with the margin.
  const Eigen::Vector3d h = (0.5 * reach_m) * direction;
  const Eigen::Vector3d m = o + h - embree_centre_m;
  const Eigen::Vector3d a = h.cwiseAbs();
  const Eigen::Vector3d e = embree_half_size_m + Eigen::Vector3d::Constant(margin_m);
  if (std::abs(m.x()) > e.x() + a.x() || std::abs(m.y()) > e.y() + a.y() || std::abs(m.z()) > e.z() + a.z()) return false;
  if (std::abs(m.y() * h.z() - m.z() * h.y()) > e.y() * a.z() + e.z() * a.y()) return false;
  if (std::abs(m.z() * h.x() - m.x() * h.z()) > e.x() * a.z() + e.z() * a.x()) return false;
  if (std::abs(m.x() * h.y() - m.y() * h.x()) > e.x() * a.y() + e.y() * a.x()) return false;
  return true;
}

EmbreeRayCaster::EmbreeRayCaster(const OdeWorld& world) : impl_(std::make_unique<Impl>(world)) {
  impl_->build();
}

EmbreeRayCaster::~EmbreeRayCaster() = default;

std::optional<Hit> EmbreeRayCaster::cast(const Ray& ray) const {
  const auto checked = detail::check_ray(ray);
  if (!checked) return std::nullopt;
  CastContext context;  // not value-initialised: zeroing Embree's part first cost ~10 % of a cast
  rtcInitIntersectContext(&context.embree);
  context.ray = &*checked;
  context.local_origin = checked->origin_m - impl_->frame_origin_m;
  if (checked->ignored_object < impl_->primitive_by_object.size()) {
    context.ignored_primitive = impl_->primitive_by_object[checked->ignored_object];
  }
  // Planes are unbounded, so they stay out of the BVH and only shorten the query.
  for (const detail::ExactPlane& plane : impl_->planes) {
    const auto contact = detail::intersect(plane, *checked);
    if (contact && (!context.best || detail::nearer(*contact, *context.best))) context.best = contact;
  }
  const auto best_hit = [&]() -> std::optional<Hit> {
    if (!context.best) return std::nullopt;
    return detail::to_hit(*context.best, *checked, impl_->world);
  };
  if (impl_->primitives.object_indices.empty() && impl_->meshes.empty()) return best_hit();

  const Eigen::Vector3d& local_origin = context.local_origin;
  const double reach_m = context.best ? context.best->range_m : checked->max_range_m;
  if (!impl_->may_meet_embree_geometry(local_origin, checked->direction, round_up_to_float(reach_m))) return best_hit();
  // Embree's float copy of the ray deviates by ~2^-24 of its origin's distance from the frame
  // centre; from far away (a small scene seen from 800 m) that exceeded the boxes' padding and
  // Embree dropped objects the ray hits (issue 26). Its float ray therefore starts at most two
  // radii of the geometry before the point of the ray closest to the geometry's centre; the
  // exact tests still use the double ray from its true origin.
  const double along_m = (impl_->embree_centre_m - local_origin).dot(checked->direction);
  context.skip_m = std::max(0.0, along_m - 2.0 * impl_->embree_radius_m);
  if (context.skip_m >= reach_m) return best_hit();
  const Eigen::Vector3d start = local_origin + context.skip_m * checked->direction;
  RTCRayHit rayhit{};
  rayhit.ray.org_x = to_float(start.x());
  rayhit.ray.org_y = to_float(start.y());
  rayhit.ray.org_z = to_float(start.z());
  rayhit.ray.dir_x = static_cast<float>(checked->direction.x());
  rayhit.ray.dir_y = static_cast<float>(checked->direction.y());
  rayhit.ray.dir_z = static_cast<float>(checked->direction.z());
  rayhit.ray.tnear = 0.0f;
  rayhit.ray.tfar = round_up_to_float(reach_m - context.skip_m);
  rayhit.ray.mask = 0xFFFFFFFFu;
  rayhit.ray.time = 0.0f;
  rayhit.ray.flags = 0;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context.embree, &rayhit);

  // The nearest triangle by double range, if any; a plane or primitive nearer in double wins
  // (Embree's last record may be either: a primitive accepted after a triangle overwrites it).
  if (context.triangle_geom_id == RTC_INVALID_GEOMETRY_ID) return best_hit();
  const Hit triangle = impl_->mesh_hit(*checked, context);
  if (context.best && !detail::nearer(detail::Contact{triangle.range_m, triangle.normal, triangle.object_index}, *context.best)) {
    return best_hit();
  }
  return triangle;
}

}  // namespace ldoem::raycast
