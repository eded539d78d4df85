#include <gtest/gtest.h>
#include <png.h>

#include <csetjmp>
#include <cstring>

#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/cloud/range_image.hpp"
#include "sample_clouds.hpp"

namespace ldoem::cloud {
namespace {

// What libpng reads back from a file: the test's independent check of the encoder.
struct DecodedPng {
  bool ok = false;
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int color_type = -1;
  std::vector<std::uint16_t> pixels;
};

struct MemoryReader {
  const std::string* bytes;
  std::size_t offset;
};

void read_from_memory(png_structp png, png_bytep out, png_size_t length) {
  auto* reader = static_cast<MemoryReader*>(png_get_io_ptr(png));
  if (reader->offset + length > reader->bytes->size()) png_error(png, "read past end");
  std::memcpy(out, reader->bytes->data() + reader->offset, length);
  reader->offset += length;
}

void read_rows(png_structp png, png_infop info, DecodedPng& decoded, std::vector<png_byte>& row) {
  png_read_info(png, info);
  decoded.width = png_get_image_width(png, info);
  decoded.height = png_get_image_height(png, info);
  decoded.bit_depth = png_get_bit_depth(png, info);
  decoded.color_type = png_get_color_type(png, info);
  row.resize(png_get_rowbytes(png, info));
  for (png_uint_32 y = 0; y < decoded.height; ++y) {
    png_read_row(png, row.data(), nullptr);
    for (png_uint_32 x = 0; x < decoded.width; ++x) {
      decoded.pixels.push_back(decoded.bit_depth == 16 ? static_cast<std::uint16_t>((row[2 * x] << 8) | row[2 * x + 1])
                                                       : row[x]);
    }
  }
  png_read_end(png, nullptr);
  decoded.ok = true;
}

bool read_guarded(png_structp png, png_infop info, DecodedPng& decoded, std::vector<png_byte>& row) {
  if (setjmp(png_jmpbuf(png))) return false;
  read_rows(png, info, decoded, row);
  return true;
}

DecodedPng decode_png(const std::string& bytes) {
  DecodedPng decoded;
  if (bytes.size() < 8 || png_sig_cmp(reinterpret_cast<png_const_bytep>(bytes.data()), 0, 8) != 0) return decoded;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  MemoryReader reader{&bytes, 0};
  std::vector<png_byte> row;
  png_set_read_fn(png, &reader, read_from_memory);
  if (!read_guarded(png, info, decoded, row)) decoded.ok = false;
  png_destroy_read_struct(&png, &info, nullptr);
  return decoded;
}

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

TEST(RangeImage, PngReadBackByLibpng_HasDimensionsAndPixels) {
  for (const PngBitDepth depth : {PngBitDepth::eight, PngBitDepth::sixteen}) {
    RangeImageOptions options;
    options.bit_depth = depth;
    const auto png = encode_png(make_range_image(layered_cloud(), options).value());
    ASSERT_TRUE(png);
    const DecodedPng decoded = decode_png(*png);
    ASSERT_TRUE(decoded.ok);
    EXPECT_EQ(decoded.width, 4U);
    EXPECT_EQ(decoded.height, 3U);
    EXPECT_EQ(decoded.color_type, PNG_COLOR_TYPE_GRAY);
    EXPECT_EQ(decoded.bit_depth, static_cast<int>(depth));
    const std::uint16_t brightest = depth == PngBitDepth::eight ? 255 : 65535;
    EXPECT_EQ(decoded.pixels[0], brightest);
    EXPECT_EQ(decoded.pixels[2], 1);
    EXPECT_EQ(decoded.pixels[7], 0);
  }
}

TEST(RangeImage, WrittenFile_IsValidPngOfSameBytes) {
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) / "range.png";
  const auto written = write_range_image_png(path, layered_cloud());
  ASSERT_TRUE(written);
  const std::string bytes = read_file_bytes(path).value();
  EXPECT_EQ(bytes.size(), *written);
  EXPECT_TRUE(decode_png(bytes).ok);
  EXPECT_EQ(bytes, encode_png(make_range_image(layered_cloud()).value()).value());  // deterministic
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
  options.bit_depth = PngBitDepth::eight;
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
