#include "neighbour_grid.hpp"

#include <cmath>

#include <Eigen/Eigenvalues>

namespace ldoem::cloud::detail {

NeighbourGrid::NeighbourGrid(std::span<const Eigen::Vector3d> points, double radius_m)
    : points_(points), radius_m_(radius_m) {
  for (std::size_t index = 0; index < points.size(); ++index) {
    cells_[key_of(cell_of(points[index]))].push_back(index);
  }
}

NeighbourGrid::Cell NeighbourGrid::cell_of(const Eigen::Vector3d& point) const {
  return Cell{static_cast<std::int64_t>(std::floor(point.x() / radius_m_)),
              static_cast<std::int64_t>(std::floor(point.y() / radius_m_)),
              static_cast<std::int64_t>(std::floor(point.z() / radius_m_))};
}

// 21 bits per axis; cells further apart than 2^21 radii alias, which only costs distance checks.
std::uint64_t NeighbourGrid::key_of(const Cell& cell) {
  constexpr std::uint64_t mask = (1ULL << 21) - 1;
  return ((static_cast<std::uint64_t>(cell.x) & mask) << 42) |
         ((static_cast<std::uint64_t>(cell.y) & mask) << 21) | (static_cast<std::uint64_t>(cell.z) & mask);
}

std::vector<std::size_t> NeighbourGrid::neighbours_of(std::size_t index) const {
  const Eigen::Vector3d& centre = points_[index];
  const Cell home = cell_of(centre);
  std::vector<std::size_t> found;
  for (std::int64_t dx = -1; dx <= 1; ++dx) {
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      for (std::int64_t dz = -1; dz <= 1; ++dz) {
        const auto cell = cells_.find(key_of(Cell{home.x + dx, home.y + dy, home.z + dz}));
        if (cell == cells_.end()) continue;
        for (std::size_t candidate : cell->second) {
          if ((points_[candidate] - centre).norm() <= radius_m_) found.push_back(candidate);
        }
      }
    }
  }
  return found;
}

std::optional<Eigen::Vector3d> NeighbourGrid::normal_at(std::size_t index) const {
  const std::vector<std::size_t> neighbours = neighbours_of(index);
  constexpr std::size_t minimum_neighbours = 5;
  if (neighbours.size() < minimum_neighbours) return std::nullopt;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (std::size_t neighbour : neighbours) centroid += points_[neighbour];
  centroid /= static_cast<double>(neighbours.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (std::size_t neighbour : neighbours) {
    const Eigen::Vector3d centred = points_[neighbour] - centroid;
    scatter += centred * centred.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  // A line of points (one scan row) has two small eigenvalues: its normal is undefined.
  if (!(solver.eigenvalues()(1) > 4.0 * solver.eigenvalues()(0))) return std::nullopt;
  return solver.eigenvectors().col(0).normalized();
}

}  // namespace ldoem::cloud::detail
