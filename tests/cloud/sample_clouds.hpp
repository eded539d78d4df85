// Small clouds shared by the codec tests.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "ldoem/cloud/point_cloud.hpp"

namespace ldoem::cloud::testing {

inline PointRecord point_at(Point3f position, float intensity = 0.0F, std::uint16_t ring = 0) {
  PointRecord record;
  record.position = position;
  record.intensity = intensity;
  record.ring = ring;
  return record;
}

// Three points with awkward values: a negative, a non-representable decimal, a large value.
inline PointCloud three_point_cloud(CloudChannels channels) {
  PointCloud cloud(channels);
  cloud.push_back(PointRecord{{1.0F, -2.5F, 0.125F}, 100.0F, 0, {0, 0}});
  cloud.push_back(PointRecord{{0.1F, 3.3333333F, -7.75F}, 65535.0F, 1, {0, 1}});
  cloud.push_back(PointRecord{{1234.5678F, 1e-7F, -0.0F}, 0.5F, 65535, {1, 0}});
  return cloud;
}

inline PointCloud all_channels_cloud() {
  return three_point_cloud(CloudChannels{.intensity = true, .ring = true, .image_position = false});
}

// Compares everything the files carry (positions bit for bit, NaN equal to NaN).
inline bool same_file_content(const PointCloud& a, const PointCloud& b) {
  if (a.size() != b.size() || a.channels().intensity != b.channels().intensity ||
      a.channels().ring != b.channels().ring) {
    return false;
  }
  const auto same_float = [](float x, float y) { return (std::isnan(x) && std::isnan(y)) || std::bit_cast<std::uint32_t>(x) == std::bit_cast<std::uint32_t>(y); };
  for (std::size_t i = 0; i < a.size(); ++i) {
    const PointRecord ra = a.record(i);
    const PointRecord rb = b.record(i);
    if (!same_float(ra.position.x_m, rb.position.x_m) || !same_float(ra.position.y_m, rb.position.y_m) ||
        !same_float(ra.position.z_m, rb.position.z_m) || !same_float(ra.intensity, rb.intensity) ||
        ra.ring != rb.ring) {
      return false;
    }
  }
  return true;
}

}  // namespace ldoem::cloud::testing
