// ldoem-scan --render: a perspective picture of a cloud, coloured by height or intensity.
#include "ldoem/cloud/cloud_render.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>

namespace ldoem::cloud {
namespace {

// A floor (z = 0) ahead of the scanner and a 1 m post standing on it, with intensity rising
// along x.
PointCloud floor_and_post() {
  PointCloud cloud(CloudChannels{.intensity = true});
  for (int i = 0; i < 100; ++i) {
    for (int j = -50; j < 50; ++j) {
      cloud.push_back({Point3f{2.0F + 0.08F * i, 0.08F * j, 0.0F}, static_cast<float>(i), 0, {}});
    }
  }
  for (int k = 0; k < 200; ++k) {
    cloud.push_back({Point3f{6.0F, 0.0F, 0.005F * k}, 50.0F, 0, {}});
  }
  cloud.push_back({Point3f{NAN, 0.0F, 0.0F}, 0.0F, 0, {}});  // no echo: skipped
  return cloud;
}

std::size_t drawn_pixels(const image::RgbImage& picture) {
  std::size_t count = 0;
  for (std::size_t p = 0; p < picture.pixels.size(); p += 3) {
    count += !(picture.pixels[p] == 22 && picture.pixels[p + 1] == 24 && picture.pixels[p + 2] == 28);
  }
  return count;
}

TEST(CloudRender, DefaultViewIsReadableAndFillsThePicture) {
  const auto picture = render_cloud(floor_and_post());
  ASSERT_TRUE(picture);
  EXPECT_GE(picture->width, 1280u);
  EXPECT_GE(picture->height, 800u);
  ASSERT_EQ(picture->pixels.size(), std::size_t{picture->width} * picture->height * 3);
  // The floor covers a good part of the view (the default viewpoint shows the scene).
  EXPECT_GT(drawn_pixels(*picture), picture->pixels.size() / 3 / 10);
}

TEST(CloudRender, HeightAndIntensityColourDifferently) {
  const auto by_height = render_cloud(floor_and_post());
  RenderOptions options;
  options.colour = RenderColour::intensity;
  const auto by_intensity = render_cloud(floor_and_post(), options);
  ASSERT_TRUE(by_height && by_intensity);
  EXPECT_NE(by_height->pixels, by_intensity->pixels);
  // Many colours, not a grey image.
  std::set<std::uint32_t> colours;
  for (std::size_t p = 0; p < by_intensity->pixels.size(); p += 3) {
    colours.insert(by_intensity->pixels[p] << 16 | by_intensity->pixels[p + 1] << 8 | by_intensity->pixels[p + 2]);
  }
  EXPECT_GT(colours.size(), 50u);
}

TEST(CloudRender, SameCloudSamePngBytes) {
  const auto a = render_cloud(floor_and_post());
  const auto b = render_cloud(floor_and_post());
  ASSERT_TRUE(a && b);
  const auto png_a = image::encode_rgb_png(*a);
  const auto png_b = image::encode_rgb_png(*b);
  ASSERT_TRUE(png_a && png_b);
  EXPECT_EQ(*png_a, *png_b);
  ASSERT_GT(png_a->size(), 26u);
  EXPECT_EQ(static_cast<unsigned char>((*png_a)[25]), 2u) << "IHDR colour type: RGB";
}

TEST(CloudRender, RefusesWhatItCannotDraw) {
  EXPECT_EQ(render_cloud(PointCloud{}).error(), RenderError::no_points);
  PointCloud plain;
  plain.push_back({Point3f{1, 2, 3}, 0.0F, 0, {}});
  RenderOptions options;
  options.colour = RenderColour::intensity;
  EXPECT_EQ(render_cloud(plain, options).error(), RenderError::no_intensity);
  options = {};
  options.width = 100000;
  EXPECT_EQ(render_cloud(plain, options).error(), RenderError::bad_size);
  EXPECT_EQ(write_render_png("/nonexistent-dir/x.png", plain).error(), RenderError::cannot_open_file);
}

}  // namespace
}  // namespace ldoem::cloud

namespace ldoem::cloud {
namespace {

std::array<int, 3> pixel_at(const image::RgbImage& picture, std::uint32_t x, std::uint32_t y) {
  const std::size_t at = 3 * (std::size_t{y} * picture.width + x);
  return {picture.pixels[at], picture.pixels[at + 1], picture.pixels[at + 2]};
}

// The legend's colour bar sits 16 px into the 190 px band on the right, from 74 px below the
// top to 110 px above the bottom (intensity: room for the ceiling's swatch below it).
TEST(CloudRenderLegend, ColourBarRunsFromRedAtTheTopToBlueAtTheBottom) {
  RenderOptions options;
  options.width = 800;
  options.height = 500;
  options.colour = RenderColour::intensity;
  options.title = "legend test";
  const auto picture = render_cloud(floor_and_post(), options);
  ASSERT_TRUE(picture);
  const std::uint32_t bar_x = 800 - 190 + 16 + 13;
  EXPECT_EQ(pixel_at(*picture, bar_x, 74), (std::array<int, 3>{242, 63, 38}));
  EXPECT_EQ(pixel_at(*picture, bar_x, 500 - 110), (std::array<int, 3>{45, 76, 242}));
  // The ceiling's swatch below the bar, and text in the title band.
  EXPECT_EQ(pixel_at(*picture, bar_x, 500 - 110 + 38), (std::array<int, 3>{245, 110, 245}));
  std::size_t text_pixels = 0;
  for (std::uint32_t y = 0; y < 34; ++y) {
    for (std::uint32_t x = 0; x < 400; ++x) text_pixels += pixel_at(*picture, x, y) == std::array<int, 3>{225, 228, 232};
  }
  EXPECT_GT(text_pixels, 100u);
}

TEST(CloudRenderLegend, EchoAtTheCeilingHasItsOwnColourAndTheRestSpreads) {
  // Like the corridor: most echoes at 65535, the rest spread over two decades.
  PointCloud cloud(CloudChannels{.intensity = true});
  for (int i = 0; i < 100; ++i) {
    for (int j = -50; j < 50; ++j) {
      const float echo = i < 70 ? 65535.0F : static_cast<float>(1000.0 * std::pow(10.0, (i - 70) / 15.0));
      cloud.push_back({Point3f{2.0F + 0.08F * i, 0.08F * j, 0.0F}, echo, 0, {}});
    }
  }
  RenderOptions options;
  options.width = 800;
  options.height = 500;
  options.colour = RenderColour::intensity;
  const auto picture = render_cloud(cloud, options);
  ASSERT_TRUE(picture);
  std::size_t magenta = 0;
  std::set<int> hues;
  for (std::uint32_t y = 34; y < 500; ++y) {
    for (std::uint32_t x = 0; x < 800 - 190; ++x) {
      const auto [r, g, b] = pixel_at(*picture, x, y);
      magenta += r > 150 && b > 150 && g < r * 0.6;
      if (!(r > 150 && b > 150 && g < r * 0.6) && (r + g + b) > 200) hues.insert((r / 32) * 64 + (g / 32) * 8 + b / 32);
    }
  }
  EXPECT_GT(magenta, 5000u) << "echoes at the ceiling drawn in the ceiling's colour";
  EXPECT_GT(hues.size(), 12u) << "the echoes below the ceiling spread over the colour map";
}

TEST(CloudRenderLegend, SmallPicturesGetNoLabels) {
  RenderOptions options;
  options.width = 200;
  options.height = 150;
  const auto picture = render_cloud(floor_and_post(), options);
  ASSERT_TRUE(picture);
  EXPECT_NE(pixel_at(*picture, 200 - 190 + 29, 74), (std::array<int, 3>{242, 63, 38}));
}

}  // namespace
}  // namespace ldoem::cloud
