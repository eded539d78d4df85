// A point cloud as ldoem-scan produces it: positions in metres (scanner frame of D5 or the
// world frame, the caller decides) plus optional channels. Channels are chosen once, at
// construction, so every point has the same fields (PLY and PCD need one record layout).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace ldoem::cloud {

struct Point3f {
  float x_m = 0.0F;
  float y_m = 0.0F;
  float z_m = 0.0F;
  friend bool operator==(const Point3f&, const Point3f&) = default;
};

// Where a point sits in the range image: row = layer (one tilt position), column = beam (one
// head angle within the profile).
struct ImagePosition {
  std::uint32_t row_layer = 0;
  std::uint32_t column_beam = 0;
  friend bool operator==(const ImagePosition&, const ImagePosition&) = default;
};

// Which optional per-point channels a cloud carries.
struct CloudChannels {
  bool intensity = false;       // float, the ECHO value (D6) or any reflectance measure
  bool ring = false;            // uint16, the layer a point belongs to (PLY/PCD field "ring")
  bool image_position = false;  // row/column in the range image (not written to PLY/PCD)
  // float t, range, azimuth, tilt: when the beam was measured (s since the scan's first beam),
  // its measured range (m, NaN without an echo) and its direction (rad, D5's head angle and
  // tilt). PLY/PCD fields "t", "range", "azimuth", "tilt".
  bool beam = false;
  friend bool operator==(const CloudChannels&, const CloudChannels&) = default;
};

// One point with every channel; channels the cloud does not carry are ignored on push_back
// and read back as zero.
struct PointRecord {
  Point3f position;
  float intensity = 0.0F;
  std::uint16_t ring = 0;
  ImagePosition image_position;
  // The beam channel (NaN range without an echo).
  float time_s = 0.0F;
  float range_m = 0.0F;
  float azimuth_rad = 0.0F;
  float tilt_rad = 0.0F;
  // Not defaulted: NaN fields (a point without an echo) compare equal to NaN here, as a round
  // trip through a file must keep them.
  friend bool operator==(const PointRecord& a, const PointRecord& b);
};

// Organised layout in the PCD sense: height rows of width points, row-major. Points without an
// echo are kept as NaN positions so the grid stays complete.
struct OrganisedSize {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  friend bool operator==(const OrganisedSize&, const OrganisedSize&) = default;
};

class PointCloud {
 public:
  explicit PointCloud(CloudChannels channels = {});

  void reserve(std::size_t point_count);
  // Appends a point. Adding a point to an organised cloud makes it unorganised again.
  void push_back(const PointRecord& record);

  [[nodiscard]] std::size_t size() const { return positions_.size(); }
  [[nodiscard]] bool empty() const { return positions_.empty(); }
  [[nodiscard]] const CloudChannels& channels() const { return channels_; }

  [[nodiscard]] std::span<const Point3f> positions() const { return positions_; }
  // Each of these is empty when the cloud does not carry that channel, else size() long.
  [[nodiscard]] std::span<const float> intensities() const { return intensities_; }
  [[nodiscard]] std::span<const std::uint16_t> rings() const { return rings_; }
  // Empty without the beam channel; else size() long each.
  [[nodiscard]] std::span<const float> times() const { return times_; }
  [[nodiscard]] std::span<const float> ranges() const { return ranges_; }
  [[nodiscard]] std::span<const float> azimuths() const { return azimuths_; }
  [[nodiscard]] std::span<const float> tilts() const { return tilts_; }
  [[nodiscard]] std::span<const ImagePosition> image_positions() const { return image_positions_; }

  // Precondition: index < size().
  [[nodiscard]] PointRecord record(std::size_t index) const;

  // Declares the cloud organised as width x height (row-major). Returns false and changes
  // nothing when width * height != size() or either is zero.
  [[nodiscard]] bool set_organised(OrganisedSize size);
  [[nodiscard]] std::optional<OrganisedSize> organised() const { return organised_; }
  // PCD WIDTH/HEIGHT: the organised size, or (size(), 1) for an unorganised cloud.
  [[nodiscard]] OrganisedSize layout() const;

 private:
  CloudChannels channels_;
  std::vector<Point3f> positions_;
  std::vector<float> intensities_;
  std::vector<std::uint16_t> rings_;
  std::vector<float> times_;
  std::vector<float> ranges_;
  std::vector<float> azimuths_;
  std::vector<float> tilts_;
  std::vector<ImagePosition> image_positions_;
  std::optional<OrganisedSize> organised_;
};

}  // namespace ldoem::cloud
