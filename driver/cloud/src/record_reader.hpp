// Reading the point records of PLY and PCD bodies (internal). Both formats describe a point as
// a list of named scalar fields, so one reader serves both.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "codec_support.hpp"
#include "ldoem/cloud/cloud_error.hpp"
#include "ldoem/cloud/point_cloud.hpp"

namespace ldoem::cloud::detail {

struct FieldSpec {
  std::string name;
  ScalarType type = ScalarType::f32;
  std::uint32_t count = 1;  // PCD COUNT; always 1 for PLY scalar properties
};

// Errors: missing_field (x/y/z absent or not single values), truncated_data, malformed_number.
Expected<PointCloud, CloudIoError> read_binary_records(std::string_view body,
                                                       const std::vector<FieldSpec>& fields,
                                                       std::uint64_t point_count);
Expected<PointCloud, CloudIoError> read_ascii_records(std::string_view body,
                                                      const std::vector<FieldSpec>& fields,
                                                      std::uint64_t point_count);

}  // namespace ldoem::cloud::detail
