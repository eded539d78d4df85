// Vertex records common to the PLY and PCD writers.
#pragma once

#include <ldoem/cloud/point_cloud.hpp>

#include <string>

namespace ldoem::cloud::detail {

// One text line per point: "x y z[ intensity][ ring]\n".
void append_ascii_records(std::string& out, const PointCloud& cloud);
// Packed little-endian records in the same field order: float x, y, z[, float][, uint16].
void append_binary_records(std::string& out, const PointCloud& cloud);

}  // namespace ldoem::cloud::detail
