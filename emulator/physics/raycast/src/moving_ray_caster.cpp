#include "ldoem/raycast/moving_ray_caster.hpp"

#include "ldoem/raycast/ode_world.hpp"
#include "embree_device.hpp"
#include "exact_primitives.hpp"
#include "mesh_index.hpp"
#include "moving_bounds.hpp"
#include "ray_probe.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ldoem::raycast {
namespace {

// With MovingCasterOptions::refit, a refitted BVH keeps the tree of its last full build; objects
// that wander far apart make that tree slow (never wrong). A full build every this many windows
// keeps it fresh.
constexpr unsigned kWindowsPerFullBuild = 64;

struct MovingCastContext {
  RTCIntersectContext embree;  // must come first: Embree hands this pointer to the callbacks
  const detail::CheckedRay* ray = nullptr;
  double time_s = 0.0;
  const MovingRayCaster* caster = nullptr;
  std::optional<detail::Contact> best;  // object_index = moving index, normal in the world frame
  double skip_m = 0.0;  // Embree's float ray starts this far along the double one
};

void slice_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* boxes = static_cast<const std::vector<RTCBounds>*>(args->geometryUserPtr);
  *args->bounds_o = (*boxes)[args->primID];
}

void step_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* steps = static_cast<const std::vector<std::vector<RTCBounds>>*>(args->geometryUserPtr);
  *args->bounds_o = (*steps)[args->timeStep][args->primID];
}

void never_occluded(const RTCOccludedFunctionNArguments* /*args*/) {}

}  // namespace

struct MovingRayCaster::Impl {
  std::vector<std::uint32_t> scene_indices;
  const MotionSource& motion;
  MovingCasterOptions options;
  std::unique_ptr<OdeWorld> local_world;  // every moving object at the identity pose
  std::vector<detail::LocalExtent> extents;
  // Primitives in their own frame (centre 0, axes identity), tested in closed form as the static
  // caster tests them; meshes (no entry) are in `meshes`.
  std::vector<std::optional<detail::ExactPrimitive>> primitives;
  // Meshes as the static caster answers them (Embree's robust float test, the range in double
  // from the triangle's plane at the query's pose; issue 26): ODE's float trimesh missed the
  // float bound by up to 1e-4 of the range. Null for primitives; shared with
  // the mesh's TriMeshData.
  std::vector<std::shared_ptr<const detail::MeshIndex>> meshes;
  Eigen::Vector3d frame_origin_m = Eigen::Vector3d::Zero();

  std::string device_error;
  RTCDevice device = nullptr;
  std::vector<RTCScene> scenes;           // one per slice (swept_slices) or one (motion_blur)
  std::vector<RTCGeometry> geometries;
  std::vector<std::vector<RTCBounds>> boxes;  // [slice or time step][moving index]
  std::vector<TimeSpan> presence;             // empty: every object always exists
  bool prepared = false;
  // A sphere holding every box of the prepared window (frame_origin_m-relative).
  Eigen::Vector3d boxes_centre_m = Eigen::Vector3d::Zero();
  double boxes_radius_m = 0.0;
  double t0_s = 0.0;
  double t1_s = 0.0;
  unsigned windows = 0;

  Impl(const MotionSource& m, MovingCasterOptions o) : motion(m), options(o) {}
  ~Impl() {
    for (RTCGeometry g : geometries) rtcReleaseGeometry(g);
    for (RTCScene s : scenes) rtcReleaseScene(s);
    if (device != nullptr) rtcReleaseDevice(device);
  }

  void build_embree();
  void fill_boxes(std::vector<RTCBounds>& out, double a_s, double b_s) const;
  std::optional<detail::Contact> test(std::size_t k, const detail::CheckedRay& ray, double time_s,
                                      double max_range_m) const;
};

void MovingRayCaster::Impl::build_embree() {
  // One build thread: the index holds tens to thousands of boxes, which build faster in the
  // calling thread than Embree's thread pool can be woken (and the cost stays on the thread that
  // pays for it, where the benchmarks measure it).
  device = detail::new_embree_device("threads=1", device_error);
  const bool blur = options.index == MovingIndex::motion_blur;
  const unsigned scene_count = blur ? 1 : options.slices;
  boxes.assign(blur ? options.slices + 1 : options.slices, std::vector<RTCBounds>(scene_indices.size()));
  for (unsigned s = 0; s < scene_count; ++s) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(scene_indices.size()));
    if (blur) {
      rtcSetGeometryTimeStepCount(geometry, options.slices + 1);
      rtcSetGeometryUserData(geometry, &boxes);
      rtcSetGeometryBoundsFunction(geometry, step_bounds, nullptr);
    } else {
      rtcSetGeometryUserData(geometry, &boxes[s]);
      rtcSetGeometryBoundsFunction(geometry, slice_bounds, nullptr);
    }
    rtcSetGeometryIntersectFunction(geometry, [](const RTCIntersectFunctionNArguments* args) {
      if (args->N != 1 || args->valid[0] == 0) return;  // only rtcIntersect1 is used
      auto* context = reinterpret_cast<MovingCastContext*>(args->context);
      auto* rayhit = reinterpret_cast<RTCRayHit*>(args->rayhit);
      const std::size_t k = args->primID;
      if (context->caster->impl_->scene_indices[k] == context->ray->ignored_object) return;
      const double reach_m = context->best ? context->best->range_m : context->ray->max_range_m;
      const auto contact = context->caster->impl_->test(k, *context->ray, context->time_s, reach_m);
      if (!contact) return;
      // Equal ranges: the lower index wins, so the answer does not depend on traversal order.
      if (context->best && (contact->range_m > context->best->range_m ||
                            (contact->range_m == context->best->range_m && k > context->best->object_index))) {
        return;
      }
      context->best = contact;
      rayhit->ray.tfar = detail::round_up_to_float(std::max(contact->range_m - context->skip_m, 0.0));
      rayhit->hit.geomID = args->geomID;
      rayhit->hit.primID = args->primID;
    });
    rtcSetGeometryOccludedFunction(geometry, never_occluded);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    scenes.push_back(scene);
    geometries.push_back(geometry);
  }
  if (!device_error.empty()) throw std::runtime_error(device_error);
}

void MovingRayCaster::Impl::fill_boxes(std::vector<RTCBounds>& out, double a_s, double b_s) const {
  for (std::size_t k = 0; k < out.size(); ++k) {
    const scene::PathBounds path = motion.origin_bounds(k, a_s, b_s);
    detail::OffsetBox reach;
    if (motion.keeps_orientation(k)) {
      reach = detail::turned_extent(extents[k], motion.pose_at(k, a_s).orientation);
    } else if (const auto axis = motion.spin_axis(k)) {
      reach = detail::spin_extent(extents[k], motion.pose_at(k, a_s).orientation, *axis);
    } else {
      reach = detail::sphere_extent(extents[k]);
    }
    out[k] = detail::to_embree_box(path.lower_m + reach.lower_m - frame_origin_m,
                                   path.upper_m + reach.upper_m - frame_origin_m);
  }
}

// True only if the ray certainly misses the sphere of radius r about `centre` within its reach.
// The margin covers the rounding of |oc|^2 - along^2 (a few ulps of |oc|^2).
static bool misses_sphere(const Eigen::Vector3d& centre, double radius_m, const detail::CheckedRay& ray, double reach_m) {
  const Eigen::Vector3d oc = centre - ray.origin_m;
  const double along_m = oc.dot(ray.direction);
  if (along_m < -radius_m || along_m - radius_m > reach_m) return true;
  const double squared = oc.squaredNorm();
  const double margin = 1e-9 * squared + 1e-12;
  return squared - along_m * along_m > radius_m * radius_m + margin;
}

std::optional<detail::Contact> MovingRayCaster::Impl::test(std::size_t k, const detail::CheckedRay& ray,
                                                           double time_s, double max_range_m) const {
  if (!presence.empty() && !(time_s >= presence[k].from_s && time_s < presence[k].until_s)) return std::nullopt;
  // Boxes swept over a window hold many rays that miss the object at the ray's own instant: the
  // sphere about its origin rejects most of them before the pose is computed.
  if (misses_sphere(motion.position_at(k, time_s), extents[k].radius_m, ray, max_range_m)) return std::nullopt;
  const scene::Pose pose = motion.pose_at(k, time_s);
  if (!primitives[k]) return meshes[k]->intersect(ray, pose, max_range_m, k);
  const Eigen::Quaterniond inverse = pose.orientation.conjugate();
  const detail::CheckedRay local{inverse * (ray.origin_m - pose.position_m), inverse * ray.direction, max_range_m};
  auto contact = detail::intersect(*primitives[k], local);
  if (contact) contact->normal = pose.orientation * contact->normal;
  return contact;
}

MovingRayCaster::MovingRayCaster(const std::vector<scene::SceneObject>& objects,
                                 std::vector<std::uint32_t> scene_indices, const MotionSource& motion,
                                 MovingCasterOptions options, std::vector<std::shared_ptr<const TriMeshData>> meshes)
    : impl_(std::make_unique<Impl>(motion, options)) {
  if (objects.size() != scene_indices.size()) throw std::invalid_argument("MovingRayCaster: one index per object");
  if (options.slices == 0) throw std::invalid_argument("MovingRayCaster: slices must be positive");
  impl_->scene_indices = std::move(scene_indices);
  scene::Scene local;
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(INFINITY);
  Eigen::Vector3d upper = Eigen::Vector3d::Constant(-INFINITY);
  for (std::size_t k = 0; k < objects.size(); ++k) {
    scene::SceneObject object = objects[k];
    object.pose = scene::Pose{};
    object.motion.reset();
    object.dynamics.reset();
    impl_->extents.push_back(detail::local_extent(object.shape));
    local.objects.push_back(std::move(object));
    const Eigen::Vector3d p = motion.pose_at(k, 0.0).position_m;
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  if (!objects.empty()) impl_->frame_origin_m = 0.5 * (lower + upper);
  // Every mesh's data (with its index) is built here unless given, and handed to the local world.
  meshes.resize(objects.size());
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const auto* mesh = std::get_if<scene::Mesh>(&objects[k].shape);
    if (mesh != nullptr && (meshes[k] == nullptr || meshes[k]->index() == nullptr)) meshes[k] = TriMeshData::build(*mesh);
    impl_->meshes.push_back(mesh != nullptr ? meshes[k]->index() : nullptr);
  }
  impl_->local_world = std::make_unique<OdeWorld>(local, std::move(meshes));
  for (std::size_t k = 0; k < objects.size(); ++k) {
    const bool mesh = std::holds_alternative<scene::Mesh>(objects[k].shape);
    impl_->primitives.push_back(mesh ? std::nullopt
                                     : std::optional<detail::ExactPrimitive>(detail::exact_primitive_of(*impl_->local_world, k)));
  }
  impl_->build_embree();
}

MovingRayCaster::~MovingRayCaster() = default;

std::size_t MovingRayCaster::object_count() const { return impl_->scene_indices.size(); }

void MovingRayCaster::invalidate() { impl_->prepared = false; }

void MovingRayCaster::set_presence(std::vector<TimeSpan> spans) {
  if (!spans.empty() && spans.size() != impl_->scene_indices.size()) {
    throw std::invalid_argument("MovingRayCaster::set_presence: one span per object");
  }
  impl_->presence = std::move(spans);
}

void MovingRayCaster::prepare(double t0_s, double t1_s) {
  Impl& impl = *impl_;
  if (!(t1_s > t0_s) || !std::isfinite(t0_s) || !std::isfinite(t1_s)) {
    throw std::invalid_argument("MovingRayCaster::prepare: needs a finite window with t1 > t0");
  }
  if (impl.scene_indices.empty()) return;
  if (impl.prepared && t0_s >= impl.t0_s && t1_s <= impl.t1_s) return;
  t1_s = std::max(t1_s, t0_s + impl.options.min_window_s);
  const unsigned n = impl.options.slices;
  const double span_s = t1_s - t0_s;
  // Slice edges are widened by this much so that a ray time rounded across an edge still finds
  // its object in the box of either neighbour.
  const double overlap_s = 1e-6 * span_s;
  const auto edge = [&](unsigned i) { return i == n ? t1_s : t0_s + span_s * i / n; };
  if (impl.options.index == MovingIndex::swept_slices) {
    for (unsigned s = 0; s < n; ++s) impl.fill_boxes(impl.boxes[s], edge(s) - overlap_s, edge(s + 1) + overlap_s);
  } else {
    // Embree interpolates linearly between step boxes: each step's box holds the object over
    // both neighbouring segments, so every interpolated box holds it within its segment.
    for (unsigned s = 0; s <= n; ++s) {
      impl.fill_boxes(impl.boxes[s], edge(s == 0 ? 0 : s - 1) - overlap_s, edge(s == n ? n : s + 1) + overlap_s);
    }
  }
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(INFINITY), upper = -lower;
  for (const auto& step : impl.boxes) {
    for (const RTCBounds& b : step) {
      lower = lower.cwiseMin(Eigen::Vector3d(b.lower_x, b.lower_y, b.lower_z));
      upper = upper.cwiseMax(Eigen::Vector3d(b.upper_x, b.upper_y, b.upper_z));
    }
  }
  impl.boxes_centre_m = lower.allFinite() ? Eigen::Vector3d(0.5 * (lower + upper)) : Eigen::Vector3d::Zero();
  impl.boxes_radius_m = lower.allFinite() ? 0.5 * (upper - lower).norm() : INFINITY;
  const bool full_build = !impl.options.refit || impl.windows % kWindowsPerFullBuild == 0;
  for (std::size_t s = 0; s < impl.scenes.size(); ++s) {
    rtcSetGeometryBuildQuality(impl.geometries[s], full_build ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_REFIT);
    rtcCommitGeometry(impl.geometries[s]);
    rtcCommitScene(impl.scenes[s]);
  }
  ++impl.windows;
  if (!impl.device_error.empty()) throw std::runtime_error(impl.device_error);
  impl.prepared = true;
  impl.t0_s = t0_s;
  impl.t1_s = t1_s;
}

std::optional<Hit> MovingRayCaster::cast(const Ray& ray) const {
  const Impl& impl = *impl_;
  const auto checked = detail::check_ray(ray);
  if (!checked || impl.scene_indices.empty() || !std::isfinite(ray.time_s)) return std::nullopt;
  std::optional<detail::Contact> best;
  if (impl.prepared && ray.time_s >= impl.t0_s && ray.time_s <= impl.t1_s) {
    MovingCastContext context;
    rtcInitIntersectContext(&context.embree);
    context.ray = &*checked;
    context.time_s = ray.time_s;
    context.caster = this;
    const double fraction = (ray.time_s - impl.t0_s) / (impl.t1_s - impl.t0_s);
    const bool blur = impl.options.index == MovingIndex::motion_blur;
    const std::size_t slice =
        blur ? 0 : std::min<std::size_t>(static_cast<std::size_t>(fraction * impl.options.slices), impl.options.slices - 1);
    RTCRayHit rayhit{};
    // As in EmbreeRayCaster: the float ray starts near the boxes, so that its rounding stays
    // within their padding however far away the ray's origin is (issue 26).
    const Eigen::Vector3d local = checked->origin_m - impl.frame_origin_m;
    const double along_m = (impl.boxes_centre_m - local).dot(checked->direction);
    context.skip_m = std::isfinite(impl.boxes_radius_m) ? std::max(0.0, along_m - 2.0 * impl.boxes_radius_m) : 0.0;
    const Eigen::Vector3d origin = local + context.skip_m * checked->direction;
    rayhit.ray.org_x = detail::to_float(origin.x());
    rayhit.ray.org_y = detail::to_float(origin.y());
    rayhit.ray.org_z = detail::to_float(origin.z());
    rayhit.ray.dir_x = static_cast<float>(checked->direction.x());
    rayhit.ray.dir_y = static_cast<float>(checked->direction.y());
    rayhit.ray.dir_z = static_cast<float>(checked->direction.z());
    rayhit.ray.tnear = 0.0f;
    rayhit.ray.tfar = detail::round_up_to_float(std::max(checked->max_range_m - context.skip_m, 0.0));
    rayhit.ray.time = blur ? static_cast<float>(std::clamp(fraction, 0.0, 1.0)) : 0.0f;
    rayhit.ray.mask = 0xFFFFFFFFu;
    rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(impl.scenes[slice], &context.embree, &rayhit);
    best = context.best;
  } else {
    for (std::size_t k = 0; k < impl.scene_indices.size(); ++k) {
      if (impl.scene_indices[k] == checked->ignored_object) continue;
      const auto contact = impl.test(k, *checked, ray.time_s, best ? best->range_m : checked->max_range_m);
      if (contact && (!best || detail::nearer(*contact, *best))) best = contact;
    }
  }
  if (!best) return std::nullopt;
  return Hit{best->range_m, detail::facing_normal(best->normal, checked->direction),
             scene::optical_reflectance(impl.local_world->object(best->object_index)),
             impl.scene_indices[best->object_index]};
}

}  // namespace ldoem::raycast
