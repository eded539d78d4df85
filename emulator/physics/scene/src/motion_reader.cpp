#include "motion_reader.hpp"

#include "pose_reader.hpp"

#include <numbers>

namespace ldoem::scene::detail {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

bool read_bool(const std::string& file, const YAML::Node& node, const std::string& path) {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value)) {
    fail(file, SceneErrorKind::wrong_type, node, path, "must be true or false");
  }
  return value;
}

Eigen::Vector3d read_linear_velocity(const std::string& file, const YAML::Node& node, const std::string& path) {
  const Eigen::Vector3d v = read_vector3(file, node, path);
  if (!(v.norm() <= kMaxLinearSpeed_mps)) {
    fail(file, SceneErrorKind::out_of_range, node, path,
         "speed " + std::to_string(v.norm()) + " m/s is beyond " + std::to_string(int(kMaxLinearSpeed_mps)) + " m/s");
  }
  return v;
}

Eigen::Vector3d read_angular_velocity(const std::string& file, const YAML::Node& node, const std::string& path) {
  const Eigen::Vector3d w = read_vector3(file, node, path) * kRadPerDeg;
  if (!(w.norm() <= kMaxAngularSpeed_rad_s)) {
    fail(file, SceneErrorKind::out_of_range, node, path, "spin beyond 36000 deg/s (100 rev/s)");
  }
  return w;
}

Waypoint read_waypoint(const std::string& file, const YAML::Node& node, const std::string& path) {
  MapReader map(file, node, path);
  Waypoint point;
  point.t_s = read_double(file, map.require("t_s"), map.child_path("t_s"), Constraint::non_negative);
  point.position_m = read_vector3(file, map.require("position_m"), map.child_path("position_m"));
  if (auto rpy = map.get("rpy_deg")) {
    point.orientation = rotation_from_rpy_deg(read_vector3(file, *rpy, map.child_path("rpy_deg")));
  }
  map.finish();
  return point;
}

Waypoints read_waypoints(MapReader& map) {
  const std::string& file = map.file();
  Waypoints path;
  const YAML::Node list = map.require("waypoints");
  const std::string list_path = map.child_path("waypoints");
  require_sequence(file, list, list_path);
  if (list.size() < 2 || list.size() > kMaxWaypoints) {
    fail(file, SceneErrorKind::out_of_range, list, list_path, "needs 2 to 100000 waypoints");
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string point_path = list_path + "[" + std::to_string(i) + "]";
    Waypoint point = read_waypoint(file, list[i], point_path);
    if (i > 0) {
      const Waypoint& previous = path.points.back();
      if (!(point.t_s > previous.t_s)) {
        fail(file, SceneErrorKind::out_of_range, list[i]["t_s"], point_path + ".t_s",
             "times must increase strictly (previous waypoint at " + std::to_string(previous.t_s) + " s)");
      }
      const double speed = (point.position_m - previous.position_m).norm() / (point.t_s - previous.t_s);
      if (!(speed <= kMaxLinearSpeed_mps)) {
        fail(file, SceneErrorKind::out_of_range, list[i], point_path,
             "reaching it takes " + std::to_string(speed) + " m/s, beyond 1000 m/s");
      }
    }
    path.points.push_back(point);
  }
  if (auto kind = map.get("interpolation")) {
    const std::string name = read_string(file, *kind, map.child_path("interpolation"));
    if (name == "linear") {
      path.interpolation = Interpolation::linear;
    } else if (name == "cubic") {
      path.interpolation = Interpolation::cubic;
    } else {
      fail(file, SceneErrorKind::out_of_range, *kind, map.child_path("interpolation"), "must be linear or cubic");
    }
  }
  if (auto loop = map.get("loop")) path.loop = read_bool(file, *loop, map.child_path("loop"));
  return path;
}

}  // namespace

Motion read_motion(const std::string& file, const YAML::Node& node, const std::string& path) {
  MapReader map(file, node, path);
  const bool kinematic = map.has("linear_velocity_mps") || map.has("angular_velocity_dps");
  if (kinematic && map.has("waypoints")) {
    fail(file, SceneErrorKind::conflicting_keys, node, map.child_path("waypoints"),
         "give either velocities or waypoints, not both");
  }
  Motion motion;
  if (map.has("waypoints")) {
    motion = read_waypoints(map);
  } else if (kinematic) {
    ConstantVelocity velocity;
    if (auto v = map.get("linear_velocity_mps")) {
      velocity.linear_velocity_mps = read_linear_velocity(file, *v, map.child_path("linear_velocity_mps"));
    }
    if (auto w = map.get("angular_velocity_dps")) {
      velocity.angular_velocity_rad_s = read_angular_velocity(file, *w, map.child_path("angular_velocity_dps"));
    }
    motion = velocity;
  } else {
    fail(file, SceneErrorKind::missing_key, node, path,
         "needs linear_velocity_mps / angular_velocity_dps or waypoints");
  }
  map.finish();
  return motion;
}

Dynamics read_dynamics(const std::string& file, const YAML::Node& node, const std::string& path) {
  MapReader map(file, node, path);
  Dynamics dynamics;
  if (map.has("mass_kg") && map.has("density_kg_m3")) {
    fail(file, SceneErrorKind::conflicting_keys, node, map.child_path("density_kg_m3"),
         "give either mass_kg or density_kg_m3, not both");
  }
  if (auto mass = map.get("mass_kg")) {
    dynamics.mass_kg = read_double(file, *mass, map.child_path("mass_kg"), Constraint::positive);
  }
  read_field(map, "density_kg_m3", dynamics.density_kg_m3, Constraint::positive);
  if (auto v = map.get("initial_velocity_mps")) {
    dynamics.initial_velocity_mps = read_linear_velocity(file, *v, map.child_path("initial_velocity_mps"));
  }
  if (auto w = map.get("initial_angular_velocity_dps")) {
    dynamics.initial_angular_velocity_rad_s =
        read_angular_velocity(file, *w, map.child_path("initial_angular_velocity_dps"));
  }
  read_field(map, "friction", dynamics.friction, Constraint::non_negative);
  read_field(map, "restitution", dynamics.restitution, Constraint::unit_interval);
  map.finish();
  return dynamics;
}

WorldConfig read_world(const std::string& file, const YAML::Node& node, const std::string& path) {
  MapReader map(file, node, path);
  WorldConfig world;
  read_field(map, "gravity_mps2", world.gravity_mps2);
  read_step(map, "world_step_s", world.world_step_s);
  if (auto beam_time = map.get("beam_time")) {
    const std::string name = read_string(file, *beam_time, map.child_path("beam_time"));
    if (name == "per_beam") {
      world.beam_time = BeamTime::per_beam;
    } else if (name == "per_revolution") {
      world.beam_time = BeamTime::per_revolution;
    } else {
      fail(file, SceneErrorKind::out_of_range, *beam_time, map.child_path("beam_time"),
           "must be per_beam or per_revolution");
    }
  }
  map.finish();
  return world;
}

}  // namespace ldoem::scene::detail
