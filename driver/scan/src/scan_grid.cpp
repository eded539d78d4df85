#include "ldoem/scan/scan_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace ldoem::scan {
namespace {

constexpr double kRadiansPerDegreeOfTilt = std::numbers::pi / 180.0;
constexpr float kNoValue = std::numeric_limits<float>::quiet_NaN();

}  // namespace

void ScanGrid::add_layer(std::uint32_t layer, double tilt_deg, const protocol::Profile& profile,
                         const Vector3& optical_offset_m) {
  Layer entry{layer, tilt_deg, 0.0, profile_beams(profile, tilt_deg, optical_offset_m)};
  // The device clock is 16 bits of milliseconds: the time between two layers' first beams is
  // their difference modulo 2^16.
  if (!profile.sectors.empty()) {
    const std::uint16_t raw = profile.sectors.front().t_start_ms;
    if (last_start_raw_ms_) elapsed_ms_ += static_cast<std::uint16_t>(raw - *last_start_raw_ms_);
    last_start_raw_ms_ = raw;
    entry.start_ms = elapsed_ms_;
    const double offset = elapsed_ms_ - raw;
    for (Beam& beam : entry.beams) beam.device_time_ms += offset;
  }
  layers_.push_back(std::move(entry));
}

cloud::PointCloud ScanGrid::build() const {
  cloud::PointCloud cloud(kScanChannels);
  std::size_t width = 0;
  for (const Layer& layer : layers_) width = std::max(width, layer.beams.size());
  const std::size_t height = layers_.size();
  if (width == 0 || height == 0) return cloud;

  // Rows top-down by tilt (highest first; a stable order keeps equal tilts in scan order).
  std::vector<std::size_t> rows(height);
  for (std::size_t i = 0; i < height; ++i) rows[i] = i;
  std::stable_sort(rows.begin(), rows.end(),
                   [this](std::size_t a, std::size_t b) { return layers_[a].tilt_deg > layers_[b].tilt_deg; });
  // Columns: the head turns counter-clockwise seen from above (D5), so the beams of a sector
  // measured in rising angle go right to left; they are reversed unless the angles fall.
  const Layer& first = layers_.front();
  const bool rising = first.beams.size() < 2 || first.beams.back().azimuth_deg >= first.beams.front().azimuth_deg;

  const double first_ms = layers_.empty() || layers_.front().beams.empty() ? 0.0 : layers_.front().beams.front().device_time_ms;
  cloud.reserve(width * height);
  for (std::size_t row = 0; row < height; ++row) {
    const Layer& layer = layers_[rows[row]];
    for (std::size_t column = 0; column < width; ++column) {
      const std::size_t index = rising ? width - 1 - column : column;
      cloud::PointRecord record;
      record.ring = static_cast<std::uint16_t>(layer.layer);
      record.image_position = {static_cast<std::uint32_t>(row), static_cast<std::uint32_t>(column)};
      record.tilt_rad = static_cast<float>(layer.tilt_deg * kRadiansPerDegreeOfTilt);
      if (index < layer.beams.size()) {
        const Beam& beam = layer.beams[index];
        record.position = beam.position;
        record.intensity = beam.echo;
        record.range_m = static_cast<float>(beam.range_m);
        record.azimuth_rad = static_cast<float>(beam.azimuth_deg * kRadiansPerDegreeOfTilt);
        record.time_s = static_cast<float>((beam.device_time_ms - first_ms) / 1000.0);
      } else {
        // A layer with fewer beams than the widest (not seen from a device that keeps its
        // sectors): cells without a beam at all.
        record.position = {kNoValue, kNoValue, kNoValue};
        record.range_m = kNoValue;
        record.azimuth_rad = kNoValue;
        record.time_s = kNoValue;
      }
      cloud.push_back(record);
    }
  }
  (void)cloud.set_organised({static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height)});
  return cloud;
}

}  // namespace ldoem::scan
