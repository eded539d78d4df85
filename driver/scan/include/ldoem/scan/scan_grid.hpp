// The layers of a scan laid out as an organised cloud "as seen from the scanner": row 0 is the
// highest tilt, column 0 the leftmost beam looking along +x (the largest head angle), so the PCD
// grid, the range image and a camera image share one orientation. Every beam has a cell; a beam
// without an echo is a NaN point (PCL's convention for an organised cloud). ring stays the
// layer's index in the order measured (0 = the first, lowest layer).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "ldoem/cloud/point_cloud.hpp"
#include "ldoem/protocol/profile.hpp"
#include "ldoem/scan/profile_points.hpp"

namespace ldoem::scan {

// Channels of a scan's cloud: intensity (ECHO), ring (layer), image position, beam (t, range,
// azimuth, tilt).
inline constexpr cloud::CloudChannels kScanChannels{true, true, true, true};

class ScanGrid {
 public:
  // Layers may come in any tilt order; each is one profile.
  void add_layer(std::uint32_t layer, double tilt_deg, const protocol::Profile& profile,
                 const Vector3& optical_offset_m);

  // The organised cloud: width = the most beams of a layer, height = the layers added. t is in
  // seconds since the first beam of the first layer added, from the profiles' TSTART/TEND
  // (unwrapped at 2^16 ms between layers, so layers must come less than 65.5 s apart).
  [[nodiscard]] cloud::PointCloud build() const;

 private:
  struct Layer {
    std::uint32_t layer = 0;
    double tilt_deg = 0.0;
    double start_ms = 0.0;  // device time of the first beam, unwrapped
    std::vector<Beam> beams;
  };
  std::vector<Layer> layers_;
  std::optional<std::uint16_t> last_start_raw_ms_;
  double elapsed_ms_ = 0.0;
};

}  // namespace ldoem::scan
