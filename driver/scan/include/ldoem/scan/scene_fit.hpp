// --fit: the paper's check of a scan against its scene. The largest plane is the wall; a
// cylinder with a vertical axis (D5 z) is fitted to what is left.
#pragma once

#include <string>

#include "ldoem/cloud/fitting.hpp"
#include "ldoem/cloud/point_cloud.hpp"

namespace ldoem::scan {

struct SceneFit {
  double wall_distance_m = 0.0;  // from the pivot (the cloud's origin)
  std::size_t wall_inliers = 0;
  double cylinder_diameter_m = 0.0;
  double cylinder_length_m = 0.0;
  std::size_t cylinder_inliers = 0;
};

base::Expected<SceneFit, std::string> fit_scene(const cloud::PointCloud& cloud);

// "wall distance 3.001 m (12000 points); cylinder diameter 0.400 m, length 1.20 m (800 points)"
std::string describe(const SceneFit& fit);

}  // namespace ldoem::scan
