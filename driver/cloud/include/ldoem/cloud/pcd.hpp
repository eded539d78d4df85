// PCD v0.7 (the Point Cloud Library's format). Header lines, in the order the format mandates:
//   VERSION .7 / FIELDS x y z [intensity] [ring] / SIZE 4 4 4 [4] [2] / TYPE F F F [F] [U] /
//   COUNT 1 ... / WIDTH w / HEIGHT h / VIEWPOINT 0 0 0 1 0 0 0 / POINTS n / DATA ascii|binary
// WIDTH x HEIGHT is the organised size when the cloud is organised, else (n, 1). Binary data is
// packed records in FIELDS order, little-endian, no padding.
#pragma once

#include <string>
#include <string_view>

#include "ldoem/cloud/cloud_error.hpp"
#include "ldoem/cloud/point_cloud.hpp"

namespace ldoem::cloud {

enum class PcdEncoding : std::uint8_t { ascii, binary };

[[nodiscard]] Expected<std::string, CloudIoError> encode_pcd(const PointCloud& cloud,
                                                             PcdEncoding encoding);

// Reads DATA ascii or binary (binary_compressed: unsupported_layout). Fields x, y, z are
// required; "intensity" and "ring" become channels; other fields are skipped. HEIGHT > 1 makes
// the result organised. Comment lines (#) are accepted before and between header lines.
[[nodiscard]] Expected<PointCloud, CloudIoError> decode_pcd(std::string_view file_bytes);

}  // namespace ldoem::cloud
