// The organised layout of a scan (ScanGrid) and the preview made from it: both as seen from the
// scanner, row 0 = the highest tilt, column 0 = the leftmost beam looking along +x.
#include "ldoem/scan/scan_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "ldoem/cloud/range_image.hpp"

namespace ldoem::scan {
namespace {

// Three beams at -0.25, 0, +0.25 deg (rising, as ldoem-scan configures its sectors), measured
// from t_start to t_end ms on the device clock.
protocol::Profile three_beams(std::vector<std::uint16_t> distances, std::uint16_t t_start, std::uint16_t t_end) {
  protocol::Profile profile;
  profile.format = protocol::kFormatRangeEcho;
  protocol::SectorBlock block;
  block.dir_step_ticks = 4;
  block.start_dir_ticks = static_cast<std::uint16_t>(5760 - 4);  // -0.25 deg
  block.t_start_ms = t_start;
  block.t_end_ms = t_end;
  for (std::uint16_t d : distances) block.points.push_back({d, 0, 500});
  profile.sectors.push_back(block);
  return profile;
}

TEST(ScanGrid, RowZeroIsTheHighestTiltColumnZeroTheLeftmostBeam_NaNWithoutEcho) {
  ScanGrid grid;
  // Layer 0 low (-1 deg), layer 1 high (+1 deg); the middle beam of layer 1 has no echo. The
  // device clock wraps between the layers (65530 ms, then 14 ms).
  grid.add_layer(0, -1.0, three_beams({256, 512, 768}, 65530, 65534), {});
  grid.add_layer(1, 1.0, three_beams({1024, 0, 1536}, 14, 18), {});
  const cloud::PointCloud cloud = grid.build();
  ASSERT_EQ(cloud.organised(), (cloud::OrganisedSize{3, 2}));
  ASSERT_TRUE(cloud.channels().beam);
  // Row 0 = layer 1 (highest), column 0 = beam 2 (+0.25 deg: leftmost, +y side).
  const cloud::PointRecord top_left = cloud.record(0);
  EXPECT_EQ(top_left.ring, 1);
  EXPECT_FLOAT_EQ(top_left.range_m, 6.0F);
  EXPECT_NEAR(top_left.azimuth_rad, 0.25 * M_PI / 180.0, 1e-7);
  EXPECT_NEAR(top_left.tilt_rad, M_PI / 180.0, 1e-7);
  EXPECT_GT(top_left.position.y_m, 0.0F);
  const cloud::PointRecord no_echo = cloud.record(1);
  EXPECT_TRUE(std::isnan(no_echo.position.x_m) && std::isnan(no_echo.position.y_m) &&
              std::isnan(no_echo.position.z_m) && std::isnan(no_echo.range_m));
  EXPECT_NEAR(no_echo.azimuth_rad, 0.0, 1e-7);
  const cloud::PointRecord bottom_right = cloud.record(5);
  EXPECT_EQ(bottom_right.ring, 0);
  EXPECT_FLOAT_EQ(bottom_right.range_m, 1.0F);
  EXPECT_LT(bottom_right.position.y_m, 0.0F);
  // t: 0 at the first beam measured (layer 0, beam 0 = bottom right), 2 ms per beam, and the
  // second layer 20 ms later across the clock's wrap.
  EXPECT_FLOAT_EQ(bottom_right.time_s, 0.0F);
  EXPECT_FLOAT_EQ(cloud.record(3).time_s, 0.004F);
  EXPECT_FLOAT_EQ(cloud.record(2).time_s, 0.020F);
  EXPECT_FLOAT_EQ(top_left.time_s, 0.024F);
}

TEST(ScanGrid, PreviewIsAsSeenFromTheScanner) {
  ScanGrid grid;
  grid.add_layer(0, -1.0, three_beams({256, 512, 768}, 0, 4), {});
  grid.add_layer(1, 1.0, three_beams({1024, 0, 1536}, 10, 14), {});
  cloud::PointCloud cloud = grid.build();
  cloud::RangeImageOptions options;
  options.bit_depth = image::GrayDepth::eight;
  const auto preview = cloud::make_range_image(cloud, options);
  ASSERT_TRUE(preview);
  ASSERT_EQ(preview->width, 3u);
  ASSERT_EQ(preview->height, 2u);
  // Top left: the highest layer's leftmost beam, the furthest echo (6 m): the darkest echo, 1.
  EXPECT_EQ(preview->pixels[0], 1);
  EXPECT_EQ(preview->pixels[1], 0);  // no echo
  // Bottom right: the lowest layer's rightmost beam, the nearest (1 m): the brightest.
  EXPECT_EQ(preview->pixels[5], 255);
}

}  // namespace
}  // namespace ldoem::scan
