// D12: how objects and the scanner's pivot move. Plain data filled by the scene loader, plus the
// pure evaluation of a kinematic motion at a time. Rigid-body `dynamics` are only described
// here; emulator/physics/world steps them on ODE.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

namespace ldoem::scene {

struct Pose;

// Constant velocity and spin from the object's `pose` at t = 0. The angular velocity is in the
// world frame, about the object's origin.
struct ConstantVelocity {
  Eigen::Vector3d linear_velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_rad_s = Eigen::Vector3d::Zero();
};

struct Waypoint {
  double t_s = 0.0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

enum class Interpolation : std::uint8_t {
  linear,  // straight segments between waypoints
  cubic,   // Catmull-Rom (Hermite) positions through the waypoints; orientations slerped
};

// Absolute poses at strictly increasing times (>= 2). Before the first time the object holds the
// first pose; after the last it holds the last one, or with `loop` starts over: the path repeats
// with period t_last - t_first (a loop that should close repeats its first pose last).
struct Waypoints {
  std::vector<Waypoint> points;
  Interpolation interpolation = Interpolation::linear;
  bool loop = false;
};

using Motion = std::variant<ConstantVelocity, Waypoints>;

// A real ODE body: inertia from the shape and mass (or density), contacts with the static world
// and the other bodies.
struct Dynamics {
  std::optional<double> mass_kg;        // exactly one of mass_kg and density_kg_m3 is used
  double density_kg_m3 = 1000.0;        // when mass_kg is not given
  Eigen::Vector3d initial_velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d initial_angular_velocity_rad_s = Eigen::Vector3d::Zero();
  double friction = 0.8;                // Coulomb coefficient (ODE mu)
  double restitution = 0.2;             // bounce, [0, 1]
};

// How each beam sees the world (the accuracy-versus-time knob of D12).
enum class BeamTime : std::uint8_t {
  per_beam,        // every beam at its own instant (default, what a spinning head sees)
  per_revolution,  // one snapshot at the revolution's start for all its beams (cheaper, skewless)
};

struct WorldConfig {
  Eigen::Vector3d gravity_mps2{0.0, 0.0, -9.81};
  double world_step_s = 1.0e-3;  // ODE step for `dynamics` bodies; poses interpolated between steps
  BeamTime beam_time = BeamTime::per_beam;
};

// The scene loader rejects speeds beyond these as typos (a lab scene has nothing faster).
inline constexpr double kMaxLinearSpeed_mps = 1000.0;
inline constexpr double kMaxAngularSpeed_rad_s = 2.0 * 3.14159265358979323846 * 100.0;  // 100 rev/s

// The pose at time t of a kinematic motion; `start` is the object's pose (used by
// ConstantVelocity, ignored by Waypoints, whose poses are absolute).
[[nodiscard]] Pose pose_at(const Motion& motion, const Pose& start, double t_s);

// Whether the orientation never changes (then an object's box keeps its axis-aligned extent and
// bounds can be tighter than a sphere).
[[nodiscard]] bool keeps_orientation(const Motion& motion);

// A box around every position the motion's origin takes in [t0_s, t1_s] (exact for linear
// paths, the Bezier hull of each cubic segment otherwise). `start` as for pose_at.
struct PathBounds {
  Eigen::Vector3d lower_m;
  Eigen::Vector3d upper_m;
};
[[nodiscard]] PathBounds path_bounds(const Motion& motion, const Pose& start, double t0_s, double t1_s);

}  // namespace ldoem::scene
