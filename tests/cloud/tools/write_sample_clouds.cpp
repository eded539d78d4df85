// Writes the synthetic corridor scan in all four formats plus its range image, for the
// external format check (scripts/check-cloud-formats.sh). Usage: write_sample_clouds DIR
// Prints one line per file: "<file> <width> <height>" (the organised size written).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>
#include <filesystem>
#include <iostream>

#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/cloud/range_image.hpp"
#include "../synthetic_scan.hpp"

int main(int argc, char** argv) {
  using namespace ldoem::cloud;
  if (argc != 2) {
    std::cerr << "usage: write_sample_clouds DIR\n";
    return 2;
  }
  const std::filesystem::path directory = argv[1];
  testing::SyntheticScene scene;
  scene.stray_points = 0;  // every point then has an image position
  PointCloud scan = testing::synthetic_scan(scene);
  // Laid out as ldoem-scan writes a scan: organised (width = beams, height = layers), row 0 the
  // highest layer, column 0 the leftmost beam, NaN where a beam has no echo, every channel.
  std::uint32_t beams = 0;
  std::uint32_t layers = 0;
  for (const ImagePosition& at : scan.image_positions()) {
    beams = std::max(beams, at.column_beam + 1);
    layers = std::max(layers, at.row_layer + 1);
  }
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  constexpr double degree = std::numbers::pi / 180.0;
  std::vector<PointRecord> grid(std::size_t{beams} * layers);
  for (std::uint32_t row = 0; row < layers; ++row) {
    for (std::uint32_t column = 0; column < beams; ++column) {
      PointRecord& cell = grid[std::size_t{row} * beams + column];
      const std::uint32_t layer = layers - 1 - row;
      const std::uint32_t beam = beams - 1 - column;
      cell.position = {nan, nan, nan};
      cell.range_m = nan;
      cell.ring = static_cast<std::uint16_t>(layer);
      cell.tilt_rad = static_cast<float>((scene.tilt_min_deg + layer * scene.tilt_step_deg) * degree);
      cell.azimuth_rad = static_cast<float>((scene.head_min_deg + beam * scene.head_step_deg) * degree);
      cell.time_s = static_cast<float>((std::size_t{layer} * beams + beam) * 1e-4);
      cell.image_position = {row, column};
    }
  }
  for (std::size_t index = 0; index < scan.size(); ++index) {
    const PointRecord point = scan.record(index);
    const ImagePosition at = point.image_position;
    // Dropouts: the synthetic scene hits something with every beam, a real scan does not.
    if ((at.row_layer + at.column_beam) % 101 == 0) continue;
    PointRecord& cell = grid[std::size_t{layers - 1 - at.row_layer} * beams + (beams - 1 - at.column_beam)];
    cell.position = point.position;
    cell.range_m = std::hypot(point.position.x_m, point.position.y_m, point.position.z_m);
    cell.intensity = static_cast<float>(index % 1000);
  }
  PointCloud cloud(CloudChannels{.intensity = true, .ring = true, .image_position = true, .beam = true});
  for (const PointRecord& cell : grid) cloud.push_back(cell);
  if (!cloud.set_organised({beams, layers})) return 1;
  const struct {
    const char* name;
    CloudFileFormat format;
  } files[] = {{"scan-ascii.ply", CloudFileFormat::ply_ascii},
               {"scan-binary.ply", CloudFileFormat::ply_binary},
               {"scan-ascii.pcd", CloudFileFormat::pcd_ascii},
               {"scan-binary.pcd", CloudFileFormat::pcd_binary}};
  for (const auto& file : files) {
    const auto written = write_cloud_file(directory / file.name, cloud, file.format);
    if (!written) {
      std::cerr << "write " << file.name << ": " << to_string(written.error()) << "\n";
      return 1;
    }
    std::printf("%s %u %u\n", file.name, beams, layers);
  }
  const auto png = write_range_image_png(directory / "scan-range.png", cloud);
  if (!png) {
    std::cerr << "write scan-range.png: " << to_string(png.error()) << "\n";
    return 1;
  }
  return 0;
}
