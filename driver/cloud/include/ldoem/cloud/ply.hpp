// Stanford PLY, exactly the subset PCL, Open3D and CloudCompare read for a vertex cloud:
//   ply / format ascii 1.0 | format binary_little_endian 1.0 / comment <text> /
//   element vertex N / property float x|y|z / [property float intensity] /
//   [property ushort ring] / end_header
// Binary bodies are little-endian whatever the host is (written byte by byte). ASCII values are
// the shortest text that reads back to the same float; NaN is written "nan".
#pragma once

#include <string>
#include <string_view>

#include "ldoem/cloud/cloud_error.hpp"
#include "ldoem/cloud/point_cloud.hpp"

namespace ldoem::cloud {

enum class PlyEncoding : std::uint8_t { ascii, binary_little_endian };

inline constexpr std::string_view default_ply_comment = "ldoem point cloud";

// The whole file as bytes (std::string used as a byte buffer). Errors: too_many_points,
// bad_comment (a comment holding '\r' or '\n').
[[nodiscard]] Expected<std::string, CloudIoError> encode_ply(
    const PointCloud& cloud, PlyEncoding encoding, std::string_view comment = default_ply_comment);

// Reads ascii or binary_little_endian PLY whose "vertex" element holds scalar properties;
// x, y, z are required, "intensity" and "ring" become channels, other properties are skipped.
// Elements other than vertex are allowed only after it (their data is not read).
[[nodiscard]] Expected<PointCloud, CloudIoError> decode_ply(std::string_view file_bytes);

}  // namespace ldoem::cloud
