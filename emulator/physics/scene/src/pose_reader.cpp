#include "pose_reader.hpp"

#include <numbers>

namespace ldoem::scene::detail {

Eigen::Quaterniond rotation_from_rpy_deg(const Eigen::Vector3d& rpy_deg) {
  const Eigen::Vector3d rpy_rad = rpy_deg * (std::numbers::pi / 180.0);
  return Eigen::AngleAxisd(rpy_rad.z(), Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(rpy_rad.y(), Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(rpy_rad.x(), Eigen::Vector3d::UnitX());
}

namespace {

Eigen::Quaterniond read_quaternion(const std::string& file, const YAML::Node& node,
                                   const std::string& path) {
  if (!node.IsSequence() || node.size() != 4) {
    fail(file, SceneErrorKind::wrong_type, node, path, "must be a list of 4 numbers [w, x, y, z]");
  }
  double wxyz[4];
  for (std::size_t i = 0; i < 4; ++i) {
    wxyz[i] = read_double(file, node[i], path + "[" + std::to_string(i) + "]");
  }
  Eigen::Quaterniond q(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
  // A quaternion far from unit length is more likely a typo than a rotation: accept only a
  // norm that normalisation can repair without guessing.
  const double norm = q.norm();
  if (!(norm > 1e-6) || !std::isfinite(norm)) {
    fail(file, SceneErrorKind::out_of_range, node, path, "must have a non-zero norm");
  }
  q.coeffs() /= norm;
  return q;
}

}  // namespace

Pose read_pose(const std::string& file, const YAML::Node& node, const std::string& path) {
  MapReader map(file, node, path);
  Pose pose;
  read_field(map, "position_m", pose.position_m);
  if (map.has("rpy_deg") && map.has("quaternion_wxyz")) {
    fail(file, SceneErrorKind::conflicting_keys, node, map.child_path("quaternion_wxyz"),
         "give either rpy_deg or quaternion_wxyz, not both");
  }
  if (auto rpy = map.get("rpy_deg")) {
    pose.orientation = rotation_from_rpy_deg(read_vector3(file, *rpy, map.child_path("rpy_deg")));
  }
  if (auto quaternion = map.get("quaternion_wxyz")) {
    pose.orientation = read_quaternion(file, *quaternion, map.child_path("quaternion_wxyz"));
  }
  map.finish();
  return pose;
}

}  // namespace ldoem::scene::detail

namespace ldoem::scene {

Eigen::Quaterniond rotation_from_rpy_deg(const Eigen::Vector3d& rpy_deg) { return detail::rotation_from_rpy_deg(rpy_deg); }

}  // namespace ldoem::scene
