#include "ldoem/world/scene_caster.hpp"

#include <algorithm>
#include <cmath>

namespace ldoem::world {

SceneCaster::SceneCaster(const scene::Scene& scene, raycast::MovingCasterOptions options)
    : options_(options), motion_(scene) {
  for (const scene::SceneObject& object : scene.objects) {
    Entry entry{object, object.moves(), true, nullptr};
    if (const auto* mesh = std::get_if<scene::Mesh>(&object.shape); mesh != nullptr && entry.moving) {
      entry.mesh = raycast::TriMeshData::build(*mesh);
    }
    entries_.push_back(std::move(entry));
  }
  scene_objects_ = entries_.size();
  epochs_.push_back(build_epoch(-INFINITY));
  moving_caster_ = std::make_unique<raycast::MovingRayCaster>(motion_.moving_objects(), motion_.scene_indices(),
                                                              motion_, options_, moving_meshes());
}

std::vector<std::shared_ptr<const raycast::TriMeshData>> SceneCaster::moving_meshes() const {
  std::vector<std::shared_ptr<const raycast::TriMeshData>> meshes;
  for (const std::uint32_t index : motion_.scene_indices()) meshes.push_back(entries_.at(index).mesh);
  return meshes;
}

SceneCaster::~SceneCaster() = default;

SceneCaster::StaticEpoch SceneCaster::build_epoch(double from_s) const {
  StaticEpoch epoch;
  epoch.from_s = from_s;
  scene::Scene fixed;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    if (entries_[i].moving || !entries_[i].exists) continue;
    fixed.objects.push_back(entries_[i].object);
    epoch.indices.push_back(static_cast<std::uint32_t>(i));
  }
  if (!fixed.objects.empty()) {
    epoch.world = std::make_unique<raycast::OdeWorld>(fixed);
    epoch.caster = std::make_unique<raycast::EmbreeRayCaster>(*epoch.world);
  }
  return epoch;
}

void SceneCaster::rebuild_moving_caster() {
  moving_caster_ = std::make_unique<raycast::MovingRayCaster>(motion_.moving_objects(), motion_.scene_indices(),
                                                              motion_, options_, moving_meshes());
  moving_caster_->set_presence(motion_.presence());
}

void SceneCaster::prepare(double t0_s, double t1_s) {
  // Epochs that ended before t0 can no longer be asked for: later revolutions start later.
  while (epochs_.size() > 1 && epochs_[1].from_s <= t0_s) epochs_.pop_front();
  if (motion_.moves_accepted() != moves_seen_) {  // a runtime move: the old boxes may not hold it
    moves_seen_ = motion_.moves_accepted();
    moving_caster_->invalidate();
  }
  motion_.advance(t0_s, std::max(t1_s, t0_s + options_.min_window_s));
  moving_caster_->prepare(t0_s, t1_s);
}

std::optional<raycast::Hit> SceneCaster::cast(const raycast::Ray& ray) const {
  const StaticEpoch* epoch = &epochs_.front();
  for (std::size_t e = epochs_.size(); e-- > 1;) {
    if (ray.time_s >= epochs_[e].from_s) {
      epoch = &epochs_[e];
      break;
    }
  }
  std::optional<raycast::Hit> fixed;
  if (epoch->caster) {
    raycast::Ray local = ray;  // the epoch's caster numbers its objects in epoch->indices' (ascending) order
    if (ray.ignored_object != raycast::kNoObject) {
      const auto found = std::lower_bound(epoch->indices.begin(), epoch->indices.end(), ray.ignored_object);
      local.ignored_object = found != epoch->indices.end() && *found == ray.ignored_object
                                 ? static_cast<std::uint32_t>(found - epoch->indices.begin())
                                 : raycast::kNoObject;
    }
    fixed = epoch->caster->cast(local);
    if (fixed) fixed->object_index = epoch->indices[fixed->object_index];
  }
  if (moving_caster_->object_count() == 0) return fixed;  // a static scene behind --control
  // The moving objects need only be searched up to the static hit; at an equal range the static
  // object wins (any fixed rule keeps the answer deterministic).
  raycast::Ray shorter = ray;
  if (fixed) shorter.max_range_m = fixed->range_m;
  auto moving = moving_caster_->cast(shorter);
  if (moving && (!fixed || moving->range_m < fixed->range_m)) return moving;
  return fixed;
}

base::Expected<std::monostate, std::string> SceneCaster::check_change_time(std::string_view command, double at_s) const {
  if (!std::isfinite(at_s)) return base::Unexpected(std::string(command) + ": the time must be finite");
  if (at_s < last_change_s_) {
    return base::Unexpected(std::string(command) + ": at_s " + std::to_string(at_s) + " is before a change already made at " +
                            std::to_string(last_change_s_) + " s (objects are added, removed and static ones moved in time order)");
  }
  if (epochs_.size() > kMaxPendingEpochs) {
    return base::Unexpected(std::string(command) + ": too many changes still waiting for their time");
  }
  return std::monostate{};
}

std::ptrdiff_t SceneCaster::find_static(std::string_view name) const {
  for (std::size_t i = entries_.size(); i-- > 0;) {
    if (entries_[i].exists && !entries_[i].moving && entries_[i].object.name == name) return static_cast<std::ptrdiff_t>(i);
  }
  return -1;
}

base::Expected<double, std::string> SceneCaster::move_object(std::string_view name, const scene::Pose& pose, double at_s,
                                                           bool keep_velocity) {
  if (motion_.has(name)) return motion_.move(name, pose, at_s, keep_velocity);
  const std::ptrdiff_t index = find_static(name);
  if (index < 0) return base::Unexpected<std::string>("move-object: no object named '" + std::string(name) + "'");
  if (!pose.position_m.allFinite() || !pose.orientation.coeffs().allFinite() || pose.orientation.norm() < 1e-9) {
    return base::Unexpected<std::string>("move-object: the pose must be finite");
  }
  if (pose.position_m.cwiseAbs().maxCoeff() > kWorldLimit_m) return base::Unexpected<std::string>("move-object: position beyond 1e4 m");
  Entry& entry = entries_[static_cast<std::size_t>(index)];
  if (std::holds_alternative<scene::Plane>(entry.object.shape)) {
    return base::Unexpected<std::string>("move-object: '" + std::string(name) + "' is a plane, which has no pose");
  }
  if (auto allowed = check_change_time("move-object", at_s); !allowed) return base::Unexpected(allowed.error());
  const scene::Pose before = entry.object.pose;
  entry.object.pose = pose;
  entry.object.pose.orientation.normalize();
  try {
    epochs_.push_back(build_epoch(at_s));
  } catch (const std::exception& failure) {
    entry.object.pose = before;
    return base::Unexpected<std::string>(std::string("move-object: ") + failure.what());
  }
  last_change_s_ = at_s;
  return at_s;
}

base::Expected<double, std::string> SceneCaster::add_object(scene::SceneObject object, double at_s,
                                                          std::shared_ptr<const raycast::TriMeshData> mesh) {
  if (object.name.empty()) return base::Unexpected<std::string>("add-object: the object needs a name");
  if (motion_.has(object.name) || find_static(object.name) >= 0) {
    return base::Unexpected<std::string>("add-object: an object named '" + object.name + "' exists already");
  }
  if (std::holds_alternative<scene::Plane>(object.shape)) {
    // Unbounded: no box can hold it for the moving index, and a static epoch would show it to the
    // rays but not to the bodies, which collide with the scene's own static objects only.
    return base::Unexpected<std::string>(std::string("add-object: planes are unbounded and cannot be added at runtime (no box holds them for the "
                       "moving index, and bodies collide only with the scene's own static objects); put the plane "
                       "in the scene"));
  }
  if (entries_.size() - scene_objects_ >= kMaxRuntimeObjects) {
    return base::Unexpected<std::string>("add-object: too many objects added (10000 at most)");
  }
  if (auto allowed = check_change_time("add-object", at_s); !allowed) return base::Unexpected(allowed.error());
  const auto index = static_cast<std::uint32_t>(entries_.size());
  // An added object always goes to the moving index, a still one as a motion of zero velocity,
  // a `dynamics` one as a body joining the running world: rebuilding the moving index costs
  // about 0.2 ms whatever the scene, a static index as long as building the scene (a third of a
  // second for scenes/large.yaml, docs/dynamic-scenes.md).
  if (!object.motion && !object.dynamics) object.motion = scene::ConstantVelocity{};
  double exists_from_s = at_s;
  try {
    // The mesh's tree is most of a rebuild's cost (0.2 s for scenes/meshes/large-rock.obj): the
    // daemon builds it on its import worker, and here it is built only when it was not.
    if (const auto* shape = std::get_if<scene::Mesh>(&object.shape); shape != nullptr && !mesh) {
      mesh = raycast::TriMeshData::build(*shape);
    }
    exists_from_s = motion_.add(object, index, at_s);
    entries_.push_back(Entry{std::move(object), true, true, std::move(mesh)});
    rebuild_moving_caster();
  } catch (const std::exception& failure) {
    return base::Unexpected<std::string>(std::string("add-object: ") + failure.what());
  }
  last_change_s_ = at_s;
  return exists_from_s;
}

base::Expected<double, std::string> SceneCaster::remove_object(std::string_view name, double at_s) {
  const std::ptrdiff_t index = find_static(name);
  if (index < 0 && !motion_.has(name)) return base::Unexpected<std::string>("remove-object: no object named '" + std::string(name) + "'");
  if (auto allowed = check_change_time("remove-object", at_s); !allowed) return base::Unexpected(allowed.error());
  if (motion_.has(name)) {
    for (std::size_t i = entries_.size(); i-- > 0;) {
      if (entries_[i].exists && entries_[i].moving && entries_[i].object.name == name) {
        entries_[i].exists = false;
        break;
      }
    }
    if (auto problem = motion_.remove(name, at_s)) return base::Unexpected<std::string>(*problem);
    rebuild_moving_caster();
    last_change_s_ = at_s;
    return at_s;
  }
  entries_[static_cast<std::size_t>(index)].exists = false;
  try {
    epochs_.push_back(build_epoch(at_s));
  } catch (const std::exception& failure) {
    entries_[static_cast<std::size_t>(index)].exists = true;  // nothing changed
    return base::Unexpected<std::string>(std::string("remove-object: ") + failure.what());
  }
  last_change_s_ = at_s;
  return at_s;
}

}  // namespace ldoem::world
