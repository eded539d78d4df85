#include <gtest/gtest.h>
#include <png.h>

#include "ldoem/image/png.hpp"
#include "png_reader.hpp"

namespace ldoem::image {
namespace {

using testing::decode_png;
using testing::DecodedPng;

// 4 x 3, a ramp with the extremes in it: 0 (black) and the brightest level of the depth.
GrayImage ramp(GrayDepth depth) {
  GrayImage image;
  image.width = 4;
  image.height = 3;
  image.depth = depth;
  const std::uint16_t brightest = depth == GrayDepth::eight ? 255 : 65535;
  for (std::uint16_t index = 0; index < 12; ++index) {
    image.pixels.push_back(index == 0 ? brightest : static_cast<std::uint16_t>(index * 17));
  }
  image.pixels[7] = 0;
  return image;
}

TEST(GrayPng, ReadBackByLibpng_HasDimensionsDepthAndPixels) {
  for (const GrayDepth depth : {GrayDepth::eight, GrayDepth::sixteen}) {
    const GrayImage image = ramp(depth);
    const auto png = encode_gray_png(image);
    ASSERT_TRUE(png);
    const DecodedPng decoded = decode_png(*png);
    ASSERT_TRUE(decoded.ok);
    EXPECT_EQ(decoded.width, 4U);
    EXPECT_EQ(decoded.height, 3U);
    EXPECT_EQ(decoded.color_type, PNG_COLOR_TYPE_GRAY);
    EXPECT_EQ(decoded.channels, 1);
    EXPECT_EQ(decoded.bit_depth, static_cast<int>(depth));
    EXPECT_EQ(decoded.samples, image.pixels);
  }
}

TEST(GrayPng, SixteenBit_KeepsBothBytesOfASample) {
  GrayImage image{1, 1, GrayDepth::sixteen, {0x1234}};
  const DecodedPng decoded = decode_png(encode_gray_png(image).value());
  ASSERT_TRUE(decoded.ok);
  EXPECT_EQ(decoded.samples.at(0), 0x1234);
}

TEST(GrayPng, SamePixels_SameBytes) {
  EXPECT_EQ(encode_gray_png(ramp(GrayDepth::sixteen)).value(), encode_gray_png(ramp(GrayDepth::sixteen)).value());
  EXPECT_NE(encode_gray_png(ramp(GrayDepth::sixteen)).value(), encode_gray_png(ramp(GrayDepth::eight)).value());
}

TEST(GrayPng, ZeroSide_IsEmptyImage) {
  const auto png = encode_gray_png(GrayImage{0, 3, GrayDepth::eight, {}});
  ASSERT_FALSE(png);
  EXPECT_EQ(png.error(), PngError::empty_image);
}

TEST(GrayPng, SideBeyondLimit_IsTooLarge) {
  const auto png = encode_gray_png(GrayImage{kMaxPngSide + 1, 1, GrayDepth::eight, {}});
  ASSERT_FALSE(png);
  EXPECT_EQ(png.error(), PngError::too_large);
}

TEST(GrayPng, PixelCountNotWidthTimesHeight_IsSizeMismatch) {
  const auto png = encode_gray_png(GrayImage{2, 2, GrayDepth::eight, {1, 2, 3}});
  ASSERT_FALSE(png);
  EXPECT_EQ(png.error(), PngError::size_mismatch);
  EXPECT_EQ(to_string(png.error()), "size_mismatch");
}

}  // namespace
}  // namespace ldoem::image
