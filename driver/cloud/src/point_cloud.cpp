#include "ldoem/cloud/point_cloud.hpp"

#include <cassert>
#include <cmath>

namespace ldoem::cloud {
namespace {

bool same(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }

}  // namespace

bool operator==(const PointRecord& a, const PointRecord& b) {
  return same(a.position.x_m, b.position.x_m) && same(a.position.y_m, b.position.y_m) &&
         same(a.position.z_m, b.position.z_m) && same(a.intensity, b.intensity) && a.ring == b.ring &&
         same(a.time_s, b.time_s) && same(a.range_m, b.range_m) && same(a.azimuth_rad, b.azimuth_rad) &&
         same(a.tilt_rad, b.tilt_rad) && a.image_position == b.image_position;
}

PointCloud::PointCloud(CloudChannels channels) : channels_(channels) {}

void PointCloud::reserve(std::size_t point_count) {
  positions_.reserve(point_count);
  if (channels_.intensity) intensities_.reserve(point_count);
  if (channels_.ring) rings_.reserve(point_count);
  if (channels_.beam) {
    times_.reserve(point_count);
    ranges_.reserve(point_count);
    azimuths_.reserve(point_count);
    tilts_.reserve(point_count);
  }
  if (channels_.image_position) image_positions_.reserve(point_count);
}

void PointCloud::push_back(const PointRecord& record) {
  positions_.push_back(record.position);
  if (channels_.intensity) intensities_.push_back(record.intensity);
  if (channels_.ring) rings_.push_back(record.ring);
  if (channels_.beam) {
    times_.push_back(record.time_s);
    ranges_.push_back(record.range_m);
    azimuths_.push_back(record.azimuth_rad);
    tilts_.push_back(record.tilt_rad);
  }
  if (channels_.image_position) image_positions_.push_back(record.image_position);
  organised_.reset();
}

PointRecord PointCloud::record(std::size_t index) const {
  assert(index < size());
  PointRecord out;
  out.position = positions_[index];
  if (channels_.intensity) out.intensity = intensities_[index];
  if (channels_.ring) out.ring = rings_[index];
  if (channels_.beam) {
    out.time_s = times_[index];
    out.range_m = ranges_[index];
    out.azimuth_rad = azimuths_[index];
    out.tilt_rad = tilts_[index];
  }
  if (channels_.image_position) out.image_position = image_positions_[index];
  return out;
}

bool PointCloud::set_organised(OrganisedSize organised_size) {
  const std::uint64_t cells =
      std::uint64_t{organised_size.width} * std::uint64_t{organised_size.height};
  if (organised_size.width == 0 || organised_size.height == 0 || cells != size()) return false;
  organised_ = organised_size;
  return true;
}

OrganisedSize PointCloud::layout() const {
  if (organised_) return *organised_;
  return OrganisedSize{static_cast<std::uint32_t>(size()), 1};
}

}  // namespace ldoem::cloud
