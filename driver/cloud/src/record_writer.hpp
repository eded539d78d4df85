// Vertex records common to the PLY and PCD writers.
#pragma once

#include <ldoem/cloud/point_cloud.hpp>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace ldoem::cloud::detail {

// A field as both headers declare it: every field is a 4-byte float except ring (uint16).
struct FieldDeclaration {
  std::string_view name;
  bool is_ring = false;
};

// The fields written for a cloud with these channels, in file order:
// x y z [intensity] [t range azimuth tilt] [ring].
std::vector<FieldDeclaration> written_fields(const CloudChannels& channels);

// One text line per point, the fields above separated by spaces.
void append_ascii_records(std::string& out, const PointCloud& cloud);
// Packed little-endian records in the same field order: floats, then ring as uint16.
void append_binary_records(std::string& out, const PointCloud& cloud);

}  // namespace ldoem::cloud::detail
