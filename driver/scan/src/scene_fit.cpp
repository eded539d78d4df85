#include "ldoem/scan/scene_fit.hpp"

#include <cstdio>
#include <numbers>

namespace ldoem::scan {

base::Expected<SceneFit, std::string> fit_scene(const cloud::PointCloud& cloud) {
  const std::vector<Eigen::Vector3d> points = cloud::finite_positions(cloud);
  auto wall = cloud::fit_plane_ransac(points);
  if (!wall) {
    return base::Unexpected<std::string>("wall plane: " + std::string(cloud::to_string(wall.error())));
  }
  std::vector<Eigen::Vector3d> rest;
  std::size_t next_inlier = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (next_inlier < wall->inliers.size() && wall->inliers[next_inlier] == i) {
      ++next_inlier;
      continue;
    }
    rest.push_back(points[i]);
  }
  cloud::CylinderRansacOptions options;
  options.axis_hint = cloud::AxisHint{Eigen::Vector3d::UnitZ(), 0.2};
  auto cylinder = cloud::fit_cylinder_ransac(rest, options);
  if (!cylinder) {
    return base::Unexpected<std::string>("cylinder: " + std::string(cloud::to_string(cylinder.error())));
  }
  return SceneFit{wall->offset_m, wall->inlier_count, 2.0 * cylinder->radius_m, cylinder->length_m,
                  cylinder->inlier_count};
}

std::string describe(const SceneFit& fit) {
  char line[200];
  std::snprintf(line, sizeof line, "wall distance %.4f m (%zu points); cylinder diameter %.4f m, length %.4f m (%zu points)",
                fit.wall_distance_m, fit.wall_inliers, fit.cylinder_diameter_m, fit.cylinder_length_m,
                fit.cylinder_inliers);
  return line;
}

}  // namespace ldoem::scan
