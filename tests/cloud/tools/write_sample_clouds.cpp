// Writes the synthetic corridor scan in all four formats plus its range image, for the
// external format check (scripts/check-cloud-formats.sh). Usage: write_sample_clouds DIR
// Prints one line per file: "<file> <points> <x0> <y0> <z0>" (first point, as written).
#include <cstdio>
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
  // Give the points an intensity so the optional channel is exercised too.
  PointCloud cloud(CloudChannels{.intensity = true, .ring = true, .image_position = true});
  for (std::size_t index = 0; index < scan.size(); ++index) {
    PointRecord record = scan.record(index);
    record.intensity = static_cast<float>(index % 1000);
    cloud.push_back(record);
  }
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
    const Point3f first = cloud.positions()[0];
    std::printf("%s %zu %.9g %.9g %.9g\n", file.name, cloud.size(), first.x_m, first.y_m, first.z_m);
  }
  RangeImageOptions options;
  options.last_layer_on_top = true;
  const auto png = write_range_image_png(directory / "scan-range.png", cloud, options);
  if (!png) {
    std::cerr << "write scan-range.png: " << to_string(png.error()) << "\n";
    return 1;
  }
  return 0;
}
