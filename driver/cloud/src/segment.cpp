#include <algorithm>

#include "fit_support.hpp"

namespace ldoem::cloud {
namespace {

std::vector<Eigen::Vector3d> gather(std::span<const Eigen::Vector3d> points, const std::vector<std::size_t>& indices) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(indices.size());
  for (std::size_t index : indices) out.push_back(points[index]);
  return out;
}

// Re-expresses indices into a subset as indices into the original input.
void map_back(std::vector<std::size_t>& subset_indices, const std::vector<std::size_t>& original) {
  for (std::size_t& index : subset_indices) index = original[index];
}

// Removes sorted `removed` (values) from sorted `remaining`.
std::vector<std::size_t> without(const std::vector<std::size_t>& remaining, const std::vector<std::size_t>& removed) {
  std::vector<std::size_t> out;
  std::set_difference(remaining.begin(), remaining.end(), removed.begin(), removed.end(), std::back_inserter(out));
  return out;
}

}  // namespace

Expected<CylinderSegmentation, FitError> segment_cylinder(std::span<const Eigen::Vector3d> points,
                                                          const CylinderSegmentationOptions& options) {
  if (!(options.seed_region.radius_m > 0.0) || !options.seed_region.centre.allFinite()) {
    return base::Unexpected(FitError::bad_options);
  }
  for (const Eigen::Vector3d& point : points) {
    if (!point.allFinite()) return base::Unexpected(FitError::non_finite_point);
  }
  CylinderSegmentation result;
  std::vector<std::size_t> remaining(points.size());
  for (std::size_t index = 0; index < points.size(); ++index) remaining[index] = index;

  for (std::size_t plane_number = 0; plane_number < options.max_planes; ++plane_number) {
    const std::vector<Eigen::Vector3d> subset = gather(points, remaining);
    PlaneRansacOptions plane_options = options.plane;
    plane_options.seed += plane_number;  // a different sample stream per plane, still seeded
    Expected<PlaneFit, FitError> plane = fit_plane_ransac(subset, plane_options);
    // Running out of planes is the normal end of the loop, not a failure of the segmentation.
    if (!plane || plane->inlier_count < options.min_plane_inliers) break;
    map_back(plane->inliers, remaining);
    remaining = without(remaining, plane->inliers);
    result.planes.push_back(std::move(*plane));
  }

  std::vector<std::size_t> candidates;
  for (std::size_t index : remaining) {
    if ((points[index] - options.seed_region.centre).norm() <= options.seed_region.radius_m) {
      candidates.push_back(index);
    }
  }
  result.candidate_count = candidates.size();
  Expected<CylinderFit, FitError> cylinder = fit_cylinder_ransac(gather(points, candidates), options.cylinder);
  if (!cylinder) return base::Unexpected(cylinder.error());
  map_back(cylinder->inliers, candidates);
  result.cylinder = std::move(*cylinder);
  return result;
}

}  // namespace ldoem::cloud
