#include "ldoem/world/world_motion.hpp"

#include <algorithm>
#include <cmath>

namespace ldoem::world {

WorldMotion::WorldMotion(const scene::Scene& scene) : bodies_(scene) {
  std::size_t body = 0;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const scene::SceneObject& object = scene.objects[i];
    if (!object.moves()) continue;
    Mover mover{object.name, object, -1, {}, true, {}};
    if (object.dynamics) {
      mover.body = static_cast<std::ptrdiff_t>(body++);
      mover.keeps_orientation = false;
    } else {
      mover.keeps_orientation = scene::keeps_orientation(*object.motion);
    }
    movers_.push_back(std::move(mover));
    scene_indices_.push_back(static_cast<std::uint32_t>(i));
  }
}

std::vector<scene::SceneObject> WorldMotion::moving_objects() const {
  std::vector<scene::SceneObject> objects;
  for (const Mover& mover : movers_) objects.push_back(mover.object);
  return objects;
}

void WorldMotion::advance(double t0_s, double t1_s) { bodies_.advance(t0_s, t1_s); }

std::optional<std::string> WorldMotion::move_object(std::string_view name, const scene::Pose& pose, double at_s) {
  auto moved = move(name, pose, at_s);
  if (!moved) return std::move(moved.error());
  return std::nullopt;
}

std::vector<WorldMotion::Mover>::iterator WorldMotion::find(std::string_view name) {
  for (auto it = movers_.rbegin(); it != movers_.rend(); ++it) {
    if (it->name == name && it->exists.until_s == INFINITY) return std::prev(it.base());
  }
  return movers_.end();
}

bool WorldMotion::has(std::string_view name) const {
  return std::any_of(movers_.begin(), movers_.end(),
                     [&](const Mover& m) { return m.name == name && m.exists.until_s == INFINITY; });
}

double WorldMotion::add(scene::SceneObject object, std::uint32_t scene_index, double from_s) {
  Mover mover{object.name, std::move(object), -1, {}, true, {from_s, INFINITY}};
  if (mover.object.dynamics) {
    mover.body = static_cast<std::ptrdiff_t>(bodies_.body_count());
    mover.exists.from_s = bodies_.add(mover.object, scene_index, from_s);
    mover.keeps_orientation = false;
  } else {
    mover.keeps_orientation = scene::keeps_orientation(*mover.object.motion);
  }
  const double exists_from_s = mover.exists.from_s;
  movers_.push_back(std::move(mover));
  scene_indices_.push_back(scene_index);
  changed_ = true;
  return exists_from_s;
}

std::optional<std::string> WorldMotion::remove(std::string_view name, double at_s) {
  const auto it = find(name);
  if (it == movers_.end()) return "remove-object: no moving object named '" + std::string(name) + "'";
  it->exists.until_s = std::max(at_s, it->exists.from_s);
  // Not before an added body has joined: its removal would come before its birth.
  if (it->body >= 0) bodies_.remove(static_cast<std::size_t>(it->body), it->exists.until_s);
  changed_ = true;
  return std::nullopt;
}

std::vector<raycast::TimeSpan> WorldMotion::presence() const {
  std::vector<raycast::TimeSpan> spans;
  if (!changed_) return spans;
  for (const Mover& mover : movers_) spans.push_back(mover.exists);
  return spans;
}

base::Expected<double, std::string> WorldMotion::move(std::string_view name, const scene::Pose& pose, double at_s,
                                                    bool keep_velocity) {
  if (!std::isfinite(at_s) || !pose.position_m.allFinite() || !pose.orientation.coeffs().allFinite()) {
    return base::Unexpected<std::string>("move-object: time and pose must be finite");
  }
  if (pose.position_m.cwiseAbs().maxCoeff() > kWorldLimit_m) {
    return base::Unexpected<std::string>("move-object: position beyond 1e4 m");
  }
  if (pose.orientation.norm() < 1e-9) return base::Unexpected<std::string>("move-object: orientation must not be zero");
  const auto it = find(name);
  if (it == movers_.end()) {
    return base::Unexpected<std::string>("move-object: no moving object named '" + std::string(name) +
           "' (only objects with motion or dynamics can be moved)");
  }
  if (at_s < it->exists.from_s) {
    return base::Unexpected<std::string>("move-object: '" + std::string(name) + "' exists only from " + std::to_string(it->exists.from_s) +
           " s (added at runtime); move it at or after that time");
  }
  scene::Pose unit = pose;
  unit.orientation.normalize();
  if (it->body >= 0) {
    const double effective_s = bodies_.place(static_cast<std::size_t>(it->body), unit, at_s, keep_velocity);
    ++moves_accepted_;
    return effective_s;
  }
  if (it->moves.size() >= kMaxMovesPerObject) {
    return base::Unexpected<std::string>("move-object: '" + std::string(name) + "' already has 1024 moves");
  }
  const auto at = std::upper_bound(it->moves.begin(), it->moves.end(), at_s,
                                   [](double t, const Move& m) { return t < m.at_s; });
  it->moves.insert(at, Move{at_s, unit});
  // A move to another orientation turns the object: its boxes must hold any orientation now.
  it->keeps_orientation = it->keeps_orientation && unit.orientation.coeffs() == it->object.pose.orientation.coeffs();
  ++moves_accepted_;
  return at_s;
}

scene::Pose WorldMotion::pose_at(std::size_t k, double t_s) const {
  const Mover& mover = movers_[k];
  if (mover.body >= 0) return bodies_.pose_at(static_cast<std::size_t>(mover.body), t_s);
  if (!mover.moves.empty() && t_s >= mover.moves.front().at_s) {
    const auto after = std::upper_bound(mover.moves.begin(), mover.moves.end(), t_s,
                                        [](double t, const Move& m) { return t < m.at_s; });
    return std::prev(after)->pose;
  }
  return scene::pose_at(*mover.object.motion, mover.object.pose, t_s);
}

Eigen::Vector3d WorldMotion::position_at(std::size_t k, double t_s) const {
  const Mover& mover = movers_[k];
  if (mover.body >= 0) return bodies_.position_at(static_cast<std::size_t>(mover.body), t_s);  // no slerp
  if (mover.body < 0 && (mover.moves.empty() || t_s < mover.moves.front().at_s)) {
    if (const auto* velocity = std::get_if<scene::ConstantVelocity>(&*mover.object.motion)) {
      return mover.object.pose.position_m + t_s * velocity->linear_velocity_mps;  // as scene::pose_at
    }
  }
  return pose_at(k, t_s).position_m;
}

scene::PathBounds WorldMotion::origin_bounds(std::size_t k, double t0_s, double t1_s) const {
  const Mover& mover = movers_[k];
  if (mover.body >= 0) return bodies_.origin_bounds(static_cast<std::size_t>(mover.body), t0_s, t1_s);
  scene::PathBounds bounds{Eigen::Vector3d::Constant(INFINITY), Eigen::Vector3d::Constant(-INFINITY)};
  const auto add = [&](const scene::PathBounds& b) {
    bounds.lower_m = bounds.lower_m.cwiseMin(b.lower_m);
    bounds.upper_m = bounds.upper_m.cwiseMax(b.upper_m);
  };
  // The scene's motion until the first move, then the poses moved to.
  const double first_move = mover.moves.empty() ? INFINITY : mover.moves.front().at_s;
  if (t0_s < first_move) add(scene::path_bounds(*mover.object.motion, mover.object.pose, t0_s, std::min(t1_s, first_move)));
  for (std::size_t i = 0; i < mover.moves.size(); ++i) {
    const double end = i + 1 < mover.moves.size() ? mover.moves[i + 1].at_s : INFINITY;
    if (mover.moves[i].at_s <= t1_s && end >= t0_s) add({mover.moves[i].pose.position_m, mover.moves[i].pose.position_m});
  }
  return bounds;
}

bool WorldMotion::keeps_orientation(std::size_t k) const { return movers_[k].keeps_orientation; }

std::optional<Eigen::Vector3d> WorldMotion::spin_axis(std::size_t k) const {
  // A constant spin (scene::pose_at turns the start orientation about the angular velocity's
  // axis through the origin); a move sets other orientations, a body turns freely.
  const Mover& mover = movers_[k];
  if (mover.body >= 0 || !mover.moves.empty()) return std::nullopt;
  const auto* velocity = std::get_if<scene::ConstantVelocity>(&*mover.object.motion);
  if (velocity == nullptr || velocity->angular_velocity_rad_s.isZero(0.0)) return std::nullopt;
  return velocity->angular_velocity_rad_s.normalized();
}

}  // namespace ldoem::world
