#include "differential.hpp"

#include "ldoem/raycast/embree_ray_caster.hpp"
#include "ldoem/raycast/moving_ray_caster.hpp"
#include "ldoem/raycast/ode_world.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ldoem::oracle {
namespace {

using Eigen::Vector3d;

Vec vec(const Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Every object stays where the scene put it: the moving caster then answers the same scene.
class StandStill final : public raycast::MotionSource {
 public:
  explicit StandStill(std::vector<scene::Pose> poses) : poses_(std::move(poses)) {}
  scene::Pose pose_at(std::size_t k, double) const override { return poses_[k]; }
  scene::PathBounds origin_bounds(std::size_t k, double, double) const override {
    return {poses_[k].position_m, poses_[k].position_m};
  }
  bool keeps_orientation(std::size_t) const override { return true; }

 private:
  std::vector<scene::Pose> poses_;
};

}  // namespace

std::vector<Part> parts_of(const raycast::OdeWorld& world) {
  std::vector<Part> parts;
  for (std::size_t i = 0; i < world.object_count(); ++i) {
    const scene::SceneObject& o = world.object(i);
    Part p;
    p.object = static_cast<std::uint32_t>(i);
    if (const auto* m = std::get_if<scene::Mesh>(&o.shape)) {
      p.kind = Kind::triangle;
      for (const auto& t : m->triangles) {
        for (int k = 0; k < 3; ++k) p.vertices[k] = vec(o.pose.position_m + o.pose.orientation * m->vertices_m[t[k]].cast<double>());
        parts.push_back(p);
      }
      continue;
    }
    const dGeomID geom = world.geom(i);
    if (world.is_plane(i)) {
      dVector4 plane;
      dGeomPlaneGetParams(geom, plane);
      p.kind = Kind::plane;
      p.normal = {plane[0], plane[1], plane[2]};
      p.offset = plane[3];
      parts.push_back(p);
      continue;
    }
    const dReal* position = dGeomGetPosition(geom);
    const dReal* rotation = dGeomGetRotation(geom);
    p.centre = {position[0], position[1], position[2]};
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 3; ++col) p.rotation[3 * row + col] = rotation[4 * row + col];
    }
    if (const auto* b = std::get_if<scene::Box>(&o.shape)) {
      p.kind = Kind::box;
      p.half = vec(0.5 * b->size_m);
    } else if (const auto* s = std::get_if<scene::Sphere>(&o.shape)) {
      p.kind = Kind::sphere;
      p.radius = s->radius_m;
    } else if (const auto* c = std::get_if<scene::Cylinder>(&o.shape)) {
      p.kind = Kind::cylinder;
      p.radius = c->radius_m;
      p.half_length = 0.5 * c->length_m;
    } else if (const auto* c = std::get_if<scene::Capsule>(&o.shape)) {
      p.kind = Kind::capsule;
      p.radius = c->radius_m;
      p.half_length = 0.5 * c->length_m;
    }
    parts.push_back(p);
  }
  return parts;
}

namespace {

double distance(const Vec& a, const Vec& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

// The centre of Embree's float frame: the middle of the bounds of every primitive's AABB and
// mesh vertex (EmbreeRayCaster::Impl::build).
Vec embree_frame(const raycast::OdeWorld& world, const std::vector<Part>& parts) {
  Vector3d lower = Vector3d::Constant(INFINITY), upper = -lower;
  for (std::size_t i = 0; i < world.object_count(); ++i) {
    if (world.is_plane(i) || world.is_mesh(i)) continue;
    dReal aabb[6];
    dGeomGetAABB(world.geom(i), aabb);
    lower = lower.cwiseMin(Vector3d(aabb[0], aabb[2], aabb[4]));
    upper = upper.cwiseMax(Vector3d(aabb[1], aabb[3], aabb[5]));
  }
  for (const Part& p : parts) {
    if (p.kind != Kind::triangle) continue;
    for (const Vec& v : p.vertices) {
      lower = lower.cwiseMin(Vector3d(v[0], v[1], v[2]));
      upper = upper.cwiseMax(Vector3d(v[0], v[1], v[2]));
    }
  }
  return lower.allFinite() ? vec(0.5 * (lower + upper)) : Vec{0, 0, 0};
}

PartScale scale_of(const Part& p, const Vec& triangle_reference) {
  switch (p.kind) {
    case Kind::plane: return {};
    case Kind::triangle: {
      double size = 0.0;
      for (const Vec& v : p.vertices) size = std::max(size, distance(v, triangle_reference));
      return {triangle_reference, size};
    }
    default:
      return {p.centre, std::max({p.half[0], p.half[1], p.half[2], p.radius + p.half_length})};
  }
}

std::string describe_ray(const raycast::Ray& r) {
  std::ostringstream s;
  s.precision(17);
  s << "origin (" << r.origin_m.x() << ", " << r.origin_m.y() << ", " << r.origin_m.z() << ") direction (" << r.direction.x()
    << ", " << r.direction.y() << ", " << r.direction.z() << ") reach " << r.max_range_m;
  if (r.ignored_object != raycast::kNoObject) s << " ignoring " << r.ignored_object;
  return s.str();
}

void tally(Stats& stats, const Verdict& v, Engine engine, const std::vector<Part>& parts, const raycast::Ray& ray,
           const std::string& describe) {
  ++stats.rays;
  if (v.exact) ++stats.exact;
  if (v.excused) ++stats.excused;
  const char* engine_name = engine == Engine::embree ? "embree" : "moving";
  switch (v.fault) {
    case Fault::none: break;
    case Fault::not_finite: ++stats.not_finite; break;
    case Fault::wrong_object: ++stats.wrong_object; break;
    case Fault::range: ++stats.range_faults; break;
    case Fault::missed: ++stats.missed; break;
    case Fault::oracle_failed: ++stats.oracle_failed; break;
  }
  if (v.fault != Fault::none && v.fault != Fault::oracle_failed) {
    const std::string tag = std::string(engine_name) + " " + fault_name(v.fault);
    ++stats.faults_by[tag];
    stats.case_faults.push_back(tag + ": " + v.what);
  }
  if (v.fault != Fault::none && stats.faults.size() < 20) {
    stats.faults.push_back(std::string(engine_name) + " " + fault_name(v.fault) + ": " + v.what + (describe.empty() ? "" : "; case " + describe));
  }
  if (!v.measured) return;
  KindStats& k = stats.kinds[static_cast<std::size_t>(v.kind)];
  ++k.hits;
  k.worst_error_m = std::max(k.worst_error_m, v.error_m);
  k.worst_ulps = std::max(k.worst_ulps, v.ulps);
  if (v.cosine >= 0.5) k.worst_ulps_steep = std::max(k.worst_ulps_steep, v.ulps);
  if (v.error_m / v.bound_m > k.worst_ratio) {
    k.worst_ratio = v.error_m / v.bound_m;
    std::ostringstream s;
    s.precision(3);
    s << engine_name << ", error " << v.error_m << " m (" << v.ulps << " ulps), bound " << v.bound_m << " m, part "
      << v.part << " of " << parts.size() << ", ray " << describe_ray(ray);
    k.worst_case = s.str() + (describe.empty() ? "" : ", case " + describe);
  }
}

}  // namespace

void Stats::merge(const Stats& o) {
  cases += o.cases;
  rays += o.rays;
  exact += o.exact;
  excused += o.excused;
  wrong_object += o.wrong_object;
  range_faults += o.range_faults;
  missed += o.missed;
  not_finite += o.not_finite;
  oracle_failed += o.oracle_failed;
  fault_cases += o.fault_cases;
  for (const auto& [tag, count] : o.faults_by) faults_by[tag] += count;
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    KindStats& k = kinds[i];
    const KindStats& ok = o.kinds[i];
    k.hits += ok.hits;
    k.worst_error_m = std::max(k.worst_error_m, ok.worst_error_m);
    k.worst_ulps = std::max(k.worst_ulps, ok.worst_ulps);
    k.worst_ulps_steep = std::max(k.worst_ulps_steep, ok.worst_ulps_steep);
    if (ok.worst_ratio > k.worst_ratio) {
      k.worst_ratio = ok.worst_ratio;
      k.worst_case = ok.worst_case;
    }
  }
  for (const std::string& f : o.faults) {
    if (faults.size() < 20) faults.push_back(f);
  }
}

std::string Stats::text() const {
  std::ostringstream s;
  s.precision(3);
  s << "cases=" << cases << "\nrays=" << rays << "\nexact=" << exact << "\nexcused=" << excused << "\nwrong_object=" << wrong_object
    << "\nrange_faults=" << range_faults << "\nmissed=" << missed << "\nnot_finite=" << not_finite
    << "\noracle_failed=" << oracle_failed << "\nfault_cases=" << fault_cases << "\n";
  // "faults_by.moving.range=3": the caster and kind joined by a dot (scripts/numerics-report).
  for (const auto& [tag, count] : faults_by) {
    std::string key = tag;
    std::replace(key.begin(), key.end(), ' ', '.');
    s << "faults_by." << key << "=" << count << "\n";
  }
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    const KindStats& k = kinds[i];
    const std::string name = kind_name(static_cast<Kind>(i));
    s << name << ".hits=" << k.hits << "\n" << name << ".worst_error_m=" << k.worst_error_m << "\n" << name
      << ".worst_ulps=" << k.worst_ulps << "\n" << name << ".worst_ulps_steep=" << k.worst_ulps_steep << "\n" << name << ".worst_ratio=" << k.worst_ratio << "\n" << name
      << ".worst_case=" << k.worst_case << "\n";
  }
  for (const std::string& f : faults) s << "fault=" << f << "\n";
  return s.str();
}

void run_case(const OracleCase& c, Stats& stats, const std::string& describe) {
  ++stats.cases;
  const std::uint64_t faults_before = stats.fault_count();
  if (c.scene.objects.empty()) return;
  const raycast::OdeWorld world(c.scene);
  const raycast::EmbreeRayCaster embree(world);
  const std::vector<Part> parts = parts_of(world);
  const Vec frame = embree_frame(world, parts);
  std::vector<PartScale> embree_scales, moving_scales;
  for (const Part& p : parts) {
    embree_scales.push_back(scale_of(p, frame));
    moving_scales.push_back(scale_of(p, vec(c.scene.objects[p.object].pose.position_m)));
  }
  // The moving caster holds every object but the planes (they cannot move).
  std::vector<scene::SceneObject> movers;
  std::vector<std::uint32_t> indices;
  std::vector<scene::Pose> poses;
  std::vector<Part> moving_parts;
  std::vector<PartScale> moving_part_scales;
  for (std::size_t i = 0; i < c.scene.objects.size(); ++i) {
    if (world.is_plane(i)) continue;
    movers.push_back(c.scene.objects[i]);
    indices.push_back(static_cast<std::uint32_t>(i));
    poses.push_back(c.scene.objects[i].pose);
  }
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (parts[i].kind == Kind::plane) continue;
    moving_parts.push_back(parts[i]);
    moving_part_scales.push_back(moving_scales[i]);
  }
  const StandStill still(poses);
  std::unique_ptr<raycast::MovingRayCaster> moving;
  if (!movers.empty()) {
    moving = std::make_unique<raycast::MovingRayCaster>(movers, indices, still);
    moving->prepare(0.0, 1.0);
  }
  for (const raycast::Ray& ray : c.rays) {
    // The caster's own view of the ray: the reach capped at 1e9 m (ray_probe.hpp).
    const OracleRay r{vec(ray.origin_m), vec(ray.direction), std::min(ray.max_range_m, 1e9)};
    const auto answer = [](const std::optional<raycast::Hit>& h) {
      return h ? CasterAnswer{true, h->object_index, h->range_m} : CasterAnswer{};
    };
    tally(stats, judge(parts, embree_scales, r, ray.ignored_object, answer(embree.cast(ray)), Engine::embree), Engine::embree,
          parts, ray, describe);
    if (moving) {
      tally(stats, judge(moving_parts, moving_part_scales, r, ray.ignored_object, answer(moving->cast(ray)), Engine::moving),
            Engine::moving, moving_parts, ray, describe);
    }
  }
  if (stats.fault_count() > faults_before) ++stats.fault_cases;
}

}  // namespace ldoem::oracle
