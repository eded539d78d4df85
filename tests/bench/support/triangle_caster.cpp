#include "triangle_caster.hpp"

#include <embree3/rtcore.h>

#include <stdexcept>

namespace ldoem::bench {

struct EmbreeTriangleCaster::Impl {
  TriangleSoup soup;
  std::vector<double> reflectance;  // per object
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

EmbreeTriangleCaster::EmbreeTriangleCaster(const scene::Scene& scene, TriangleSoup soup)
    : impl_(std::make_unique<Impl>()) {
  impl_->soup = std::move(soup);
  for (const auto& object : scene.objects) impl_->reflectance.push_back(object.reflectance);
  impl_->device = rtcNewDevice(nullptr);
  if (impl_->device == nullptr) throw std::runtime_error("Embree: no device");
  impl_->scene = rtcNewScene(impl_->device);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const auto& vertices = impl_->soup.vertices_m;
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), vertices.size()));
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    v[3 * i + 0] = vertices[i].x();
    v[3 * i + 1] = vertices[i].y();
    v[3 * i + 2] = vertices[i].z();
  }
  const auto& triangles = impl_->soup.triangles;
  auto* index = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                3 * sizeof(unsigned), triangles.size()));
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (std::size_t k = 0; k < 3; ++k) index[3 * t + k] = triangles[t][k];
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl_->scene);
}

EmbreeTriangleCaster::~EmbreeTriangleCaster() = default;

std::size_t EmbreeTriangleCaster::triangle_count() const { return impl_->soup.triangles.size(); }

std::optional<raycast::Hit> EmbreeTriangleCaster::cast(const raycast::Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayhit{};
  rayhit.ray.org_x = static_cast<float>(ray.origin_m.x());
  rayhit.ray.org_y = static_cast<float>(ray.origin_m.y());
  rayhit.ray.org_z = static_cast<float>(ray.origin_m.z());
  rayhit.ray.dir_x = static_cast<float>(ray.direction.x());
  rayhit.ray.dir_y = static_cast<float>(ray.direction.y());
  rayhit.ray.dir_z = static_cast<float>(ray.direction.z());
  rayhit.ray.tnear = 0.0f;
  rayhit.ray.tfar = static_cast<float>(ray.max_range_m);
  rayhit.ray.mask = 0xFFFFFFFFu;
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rayhit);
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  Eigen::Vector3d normal(rayhit.hit.Ng_x, rayhit.hit.Ng_y, rayhit.hit.Ng_z);
  normal.normalize();
  if (normal.dot(ray.direction) > 0.0) normal = -normal;
  const std::uint32_t object = impl_->soup.object_index.empty() ? 0 : impl_->soup.object_index[rayhit.hit.primID];
  return raycast::Hit{rayhit.ray.tfar, normal, impl_->reflectance.empty() ? 0.0 : impl_->reflectance[object], object};
}

}  // namespace ldoem::bench
