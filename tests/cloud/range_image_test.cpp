#include <gtest/gtest.h>

#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/cloud/range_image.hpp"
#include "sample_clouds.hpp"

namespace ldoem::cloud {
namespace {

// 3 layers x 4 beams; ranges 1, 2, 3 m straight ahead; pixel (1, 3) has no echo.
PointCloud layered_cloud() {
  PointCloud cloud(CloudChannels{.image_position = true});
  for (std::uint32_t layer = 0; layer < 3; ++layer) {
    for (std::uint32_t beam = 0; beam < 4; ++beam) {
      if (layer == 1 && beam == 3) continue;
      PointRecord record;
      record.position = Point3f{static_cast<float>(1 + (layer + beam) % 3), 0.0F, 0.0F};
      record.image_position = ImagePosition{layer, beam};
      cloud.push_back(record);
    }
  }
  return cloud;
}

TEST(RangeImage, SixteenBit_NearBrightFarDimNoEchoBlack) {
  const auto image = make_range_image(layered_cloud());
  ASSERT_TRUE(image);
  EXPECT_EQ(image->width, 4U);
  EXPECT_EQ(image->height, 3U);
  EXPECT_EQ(image->pixels[0], 65535);        // layer 0 beam 0: 1 m, the nearest
  EXPECT_EQ(image->pixels[1], 32768);        // 2 m, half way
  EXPECT_EQ(image->pixels[2], 1);            // 3 m, the furthest, still not black
  EXPECT_EQ(image->pixels[1 * 4 + 3], 0);    // no echo
}

TEST(RangeImage, WrittenFile_IsTheGrayPngOfTheImage) {
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / "range.png";
  const auto written = write_range_image_png(path, layered_cloud());
  ASSERT_TRUE(written);
  const std::string bytes = read_file_bytes(path).value();
  EXPECT_EQ(bytes.size(), *written);
  EXPECT_EQ(bytes.substr(0, 8), "\x89PNG\r\n\x1a\n");
  EXPECT_EQ(bytes, image::encode_gray_png(make_range_image(layered_cloud()).value()).value());  // deterministic
}

TEST(RangeImage, LastLayerOnTop_FlipsRows) {
  RangeImageOptions options;
  options.last_layer_on_top = true;
  const auto image = make_range_image(layered_cloud(), options);
  ASSERT_TRUE(image);
  EXPECT_EQ(image->pixels[2 * 4 + 0], 65535);  // layer 0 now in the bottom row
}

TEST(RangeImage, OrganisedCloudWithNan_UsesLayoutAndNanIsBlack) {
  PointCloud cloud;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cloud.push_back(testing::point_at({2, 0, 0}));
  cloud.push_back(testing::point_at({nan, nan, nan}));
  ASSERT_TRUE(cloud.set_organised(OrganisedSize{1, 2}));
  const auto image = make_range_image(cloud);
  ASSERT_TRUE(image);
  EXPECT_EQ(image->width, 1U);
  EXPECT_EQ(image->height, 2U);
  EXPECT_EQ(image->pixels[0], 65535);
  EXPECT_EQ(image->pixels[1], 0);
}

TEST(RangeImage, FixedScale_ClampsOutsideRanges) {
  RangeImageOptions options;
  options.bit_depth = image::GrayDepth::eight;
  options.near_m = 1.5;
  options.far_m = 2.5;
  const auto image = make_range_image(layered_cloud(), options);
  ASSERT_TRUE(image);
  EXPECT_EQ(image->pixels[0], 255);  // 1 m, nearer than near
  EXPECT_EQ(image->pixels[1], 128);  // 2 m, middle
  EXPECT_EQ(image->pixels[2], 1);    // 3 m, beyond far
}

TEST(RangeImage, UnorganisedWithoutPositions_IsNoLayout) {
  PointCloud cloud;
  cloud.push_back(PointRecord{});
  const auto image = make_range_image(cloud);
  ASSERT_FALSE(image);
  EXPECT_EQ(image.error(), RangeImageError::no_image_layout);
}

TEST(RangeImage, FarNearerThanNear_IsBadScale) {
  RangeImageOptions options;
  options.near_m = 3.0;
  options.far_m = 1.0;
  const auto image = make_range_image(layered_cloud(), options);
  ASSERT_FALSE(image);
  EXPECT_EQ(image.error(), RangeImageError::bad_range_scale);
}

TEST(RangeImage, EmptyCloud_IsEmptyImage) {
  const auto image = make_range_image(PointCloud(CloudChannels{.image_position = true}));
  ASSERT_FALSE(image);
  EXPECT_EQ(image.error(), RangeImageError::empty_image);
}

}  // namespace
}  // namespace ldoem::cloud
