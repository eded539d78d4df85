// Poses in scenes: position_m plus rpy_deg (roll, pitch, yaw in degrees, R = Rz(yaw) Ry(pitch)
// Rx(roll)) or quaternion_wxyz. Internal to ldoem_scene.
#pragma once

#include "yaml_fields.hpp"

namespace ldoem::scene::detail {

Pose read_pose(const std::string& file, const YAML::Node& node, const std::string& path);
Eigen::Quaterniond rotation_from_rpy_deg(const Eigen::Vector3d& rpy_deg);

}  // namespace ldoem::scene::detail
