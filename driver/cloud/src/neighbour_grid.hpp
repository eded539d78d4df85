// Fixed-radius neighbour queries on a hashed voxel grid (internal), for local normals.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace ldoem::cloud::detail {

class NeighbourGrid {
 public:
  // Precondition: radius_m > 0, points finite.
  NeighbourGrid(std::span<const Eigen::Vector3d> points, double radius_m);
  // Indices of the points within radius_m of points[index] (itself included).
  std::vector<std::size_t> neighbours_of(std::size_t index) const;
  // Unit normal of the local surface (smallest principal axis of the neighbours), or nothing
  // with fewer than 5 neighbours or a neighbourhood that is not surface-like.
  std::optional<Eigen::Vector3d> normal_at(std::size_t index) const;

 private:
  struct Cell {
    std::int64_t x, y, z;
  };
  Cell cell_of(const Eigen::Vector3d& point) const;
  static std::uint64_t key_of(const Cell& cell);

  std::span<const Eigen::Vector3d> points_;
  double radius_m_;
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells_;
};

}  // namespace ldoem::cloud::detail
