// Whole-file helpers over the PLY and PCD codecs, for ldoem-scan and the tests.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "ldoem/cloud/cloud_error.hpp"
#include "ldoem/cloud/point_cloud.hpp"

namespace ldoem::cloud {

enum class CloudFileFormat : std::uint8_t { ply_ascii, ply_binary, pcd_ascii, pcd_binary };

// "ply-ascii", "ply-binary", "pcd-ascii", "pcd-binary" <-> the enum (for command lines).
[[nodiscard]] std::string_view to_string(CloudFileFormat format);
[[nodiscard]] std::optional<CloudFileFormat> parse_cloud_file_format(std::string_view text);

[[nodiscard]] Expected<std::string, CloudIoError> encode_cloud(const PointCloud& cloud,
                                                               CloudFileFormat format);
// Chooses PLY or PCD from the first bytes ("ply" starts a PLY file).
[[nodiscard]] Expected<PointCloud, CloudIoError> decode_cloud(std::string_view file_bytes);

// Returns the number of bytes written.
[[nodiscard]] Expected<std::size_t, CloudIoError> write_cloud_file(const std::filesystem::path& path,
                                                                   const PointCloud& cloud,
                                                                   CloudFileFormat format);
[[nodiscard]] Expected<PointCloud, CloudIoError> read_cloud_file(const std::filesystem::path& path);

// Raw file access shared with the PNG writer.
[[nodiscard]] Expected<std::size_t, CloudIoError> write_file_bytes(const std::filesystem::path& path,
                                                                   std::string_view bytes);
[[nodiscard]] Expected<std::string, CloudIoError> read_file_bytes(const std::filesystem::path& path);

}  // namespace ldoem::cloud
