#include "mesh_index.hpp"

#include "moving_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ldoem::raycast::detail {
namespace {

// Embree reports an error in the thread that caused it: each thread its own message.
thread_local std::string device_error;

// One device for every mesh index of the process, never released (indexes are built on import
// workers and the loop's thread alike, and may outlive any one caster). Embree builds and
// traverses different scenes of one device from any threads at once. One build thread: a build
// costs the thread that asks for it (an import worker, or a caster's constructor), and most
// meshes build faster than Embree's thread pool wakes.
RTCDevice mesh_device() {
  static const RTCDevice device = [] {
    RTCDevice d = rtcNewDevice("threads=1");
    if (d == nullptr) throw std::runtime_error("Embree: cannot create a device");
    rtcSetDeviceErrorFunction(d, [](void*, RTCError code, const char* text) {
      device_error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (text ? text : "");
    }, nullptr);
    return d;
  }();
  return device;
}

// One query's state for the intersection filter; Embree's context must come first.
struct MeshQuery {
  RTCIntersectContext embree;
  const MeshIndex* index = nullptr;
  const CheckedRay* ray = nullptr;
  const scene::Pose* pose = nullptr;
  const std::vector<Eigen::Vector3f>* vertices = nullptr;
  const std::vector<std::array<std::uint32_t, 3>>* triangles = nullptr;
  double skip_m = 0.0;  // Embree's float ray starts this far along the double one
  // The nearest triangle found so far by its double range (at first: the reach, and none).
  double best_m = 0.0;
  unsigned best_primitive = RTC_INVALID_GEOMETRY_ID;
};

struct TrianglePlane {
  Eigen::Vector3d normal;  // unit, zero for a degenerate triangle
  Eigen::Vector3d point;   // the first vertex, world frame
};

// The triangle's plane from its double world vertices, computed exactly as EmbreeRayCaster
// (and the oracle's parts_of) computes those vertices from the pose, so that a mesh standing
// still is the same triangle for both casters. The normal's cross product is taken component by
// component to within an ulp: for a sliver (edges 1e-7 rad apart) the plain one turned the
// normal by u / sin(angle), 1e-9 rad, which 6 m from the vertex moved the plane 6e-9 m and a
// grazing ray's range by 1e-3 m ("Findings" 8). The edges are exact when the vertices lie within
// a factor 2 of each other coordinate by coordinate (Sterbenz), as for any mesh far out.
TrianglePlane world_plane(const MeshQuery& q, unsigned primitive) {
  const auto& t = (*q.triangles)[primitive];
  const auto world = [&](std::uint32_t v) -> Eigen::Vector3d {
    return q.pose->position_m + q.pose->orientation * (*q.vertices)[v].cast<double>();
  };
  const Eigen::Vector3d a = world(t[0]);
  const Eigen::Vector3d e1 = world(t[1]) - a, e2 = world(t[2]) - a;
  const Eigen::Vector3d normal = accurate_cross(e1, e2);
  const double length = normal.norm();
  return {length > 0.0 && std::isfinite(length) ? Eigen::Vector3d(normal / length) : Eigen::Vector3d::Zero(), a};
}

// As EmbreeRayCaster's triangle_range: the double plane's range unless the ray grazes the plane
// (|n . d| <= 1e-6, zero for a degenerate triangle), then Embree's float distance.
double range_on(const TrianglePlane& plane, const CheckedRay& ray, double embree_m) {
  const double denominator = plane.normal.dot(ray.direction);
  if (std::abs(denominator) > 1e-6) {
    const double exact_m = plane.normal.dot(plane.point - ray.origin_m) / denominator;
    if (std::isfinite(exact_m)) return exact_m;
  }
  return embree_m;
}

// Keeps the triangle with the nearest double range in (0, reach] (refusing one the ray leaves
// from, issue 26, so that traversal goes on to the next one), and sets Embree's tfar from that
// double range rather than from the float distance. Embree orders triangles by float distance,
// whose error grows as 1/cos: a triangle whose plane the ray grazes may come out metres nearer
// than it is, and its float tfar then cut off a nearer, well-conditioned triangle
// (docs/numerics.md "Findings" 7). A triangle is now cut off only when its float distance lies
// beyond another's double range, that is when the two are within its own float order bound.
// Ties in double go to the lower triangle index, so that the answer does not depend on the
// traversal order (and a triangle the filter sees twice stays refused the second time).
void keep_nearest(const RTCFilterFunctionNArguments* args) {
  auto* q = reinterpret_cast<MeshQuery*>(const_cast<RTCIntersectContext*>(args->context));
  const unsigned primitive = RTCHitN_primID(args->hit, args->N, 0);
  const TrianglePlane plane = world_plane(*q, primitive);
  const double range_m = range_on(plane, *q->ray, RTCRayN_tfar(args->ray, args->N, 0) + q->skip_m);
  if (!(range_m > 0.0) || range_m > q->best_m || (range_m == q->best_m && primitive >= q->best_primitive)) {
    args->valid[0] = 0;  // Embree restores the tfar it had
    return;
  }
  q->best_m = range_m;
  q->best_primitive = primitive;
  // Never below the double range (rounded up), so that no triangle nearer in double is cut off
  // by this one's float error; Embree's traversal takes the filter's tfar.
  RTCRayN_tfar(args->ray, args->N, 0) = round_up_to_float(std::max(range_m - q->skip_m, 0.0));
}

}  // namespace

MeshIndex::MeshIndex(const scene::Mesh& mesh) : vertices_m_(mesh.vertices_m), triangles_(mesh.triangles) {
  const RTCDevice device = mesh_device();
  device_error.clear();
  scene_ = rtcNewScene(device);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), vertices_m_.size()));
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(INFINITY), upper = -lower;
  for (std::size_t v = 0; v < vertices_m_.size(); ++v) {
    for (int k = 0; k < 3; ++k) vertices[3 * v + k] = vertices_m_[v][k];
    lower = lower.cwiseMin(vertices_m_[v].cast<double>());
    upper = upper.cwiseMax(vertices_m_[v].cast<double>());
  }
  if (lower.allFinite()) {
    centre_m_ = 0.5 * (lower + upper);
    radius_m_ = 0.5 * (upper - lower).norm();
  }
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), triangles_.size()));
  for (std::size_t t = 0; t < triangles_.size(); ++t) {
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = triangles_[t][k];
  }
  rtcSetGeometryIntersectFilterFunction(geometry, keep_nearest);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene_);
  if (!device_error.empty()) {
    rtcReleaseScene(scene_);
    throw std::runtime_error(device_error);
  }
}

MeshIndex::~MeshIndex() {
  if (scene_ != nullptr) rtcReleaseScene(scene_);
}

std::optional<Contact> MeshIndex::intersect(const CheckedRay& ray, const scene::Pose& pose, double reach_m,
                                            std::size_t object_index) const {
  if (triangles_.empty()) return std::nullopt;
  MeshQuery q;
  rtcInitIntersectContext(&q.embree);
  q.index = this;
  q.ray = &ray;
  q.pose = &pose;
  q.vertices = &vertices_m_;
  q.triangles = &triangles_;
  q.best_m = reach_m;
  // The float ray, in the object's frame, starts at most two radii of the mesh before its
  // closest approach to the mesh's centre, so that its rounding stays far below the mesh's size
  // however far away the ray starts (issue 26, as in EmbreeRayCaster).
  const Eigen::Quaterniond inverse = pose.orientation.conjugate();
  const Eigen::Vector3d origin = inverse * (ray.origin_m - pose.position_m);
  const Eigen::Vector3d direction = inverse * ray.direction;
  q.skip_m = std::max(0.0, (centre_m_ - origin).dot(direction) - 2.0 * radius_m_);
  if (q.skip_m >= reach_m) return std::nullopt;
  const Eigen::Vector3d start = origin + q.skip_m * direction;
  RTCRayHit rayhit{};
  rayhit.ray.org_x = to_float(start.x());
  rayhit.ray.org_y = to_float(start.y());
  rayhit.ray.org_z = to_float(start.z());
  rayhit.ray.dir_x = static_cast<float>(direction.x());
  rayhit.ray.dir_y = static_cast<float>(direction.y());
  rayhit.ray.dir_z = static_cast<float>(direction.z());
  rayhit.ray.tnear = 0.0f;
  rayhit.ray.tfar = round_up_to_float(reach_m - q.skip_m);
  rayhit.ray.mask = 0xFFFFFFFFu;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &q.embree, &rayhit);
  if (q.best_primitive == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  // The filter's double range: recomputing it from Embree's tfar (which the filter set) would
  // change a grazing triangle's float-distance range by the rounding of that tfar.
  return Contact{q.best_m, world_plane(q, q.best_primitive).normal, object_index};
}

}  // namespace ldoem::raycast::detail
