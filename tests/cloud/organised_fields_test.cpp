// A scan's cloud through the four file formats: organised grid, NaN points, every field.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/cloud/pcd.hpp"
#include "ldoem/cloud/ply.hpp"

namespace ldoem::cloud {
namespace {

PointCloud organised_scan() {
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  PointCloud cloud(CloudChannels{.intensity = true, .ring = true, .image_position = false, .beam = true});
  for (std::uint32_t row = 0; row < 2; ++row) {
    for (std::uint32_t column = 0; column < 3; ++column) {
      PointRecord record;
      const bool echo = !(row == 1 && column == 1);
      record.position = echo ? Point3f{1.0F + column, 0.5F - 0.25F * column, 0.125F * row} : Point3f{nan, nan, nan};
      record.intensity = echo ? 1000.0F * (1 + column) : 0.0F;
      record.ring = static_cast<std::uint16_t>(1 - row);
      record.time_s = 0.001F * (3 * (1 - row) + (2 - column));
      record.range_m = echo ? 1.5F + column : nan;
      record.azimuth_rad = 0.004363F * (1.0F - column);
      record.tilt_rad = row == 0 ? 0.0174533F : -0.0174533F;
      cloud.push_back(record);
    }
  }
  EXPECT_TRUE(cloud.set_organised({3, 2}));
  return cloud;
}

class OrganisedFields : public ::testing::TestWithParam<CloudFileFormat> {};

TEST_P(OrganisedFields, RoundTripKeepsGridNaNAndEveryField) {
  const PointCloud cloud = organised_scan();
  const auto bytes = encode_cloud(cloud, GetParam());
  ASSERT_TRUE(bytes);
  const auto decoded = decode_cloud(*bytes);
  ASSERT_TRUE(decoded) << to_string(decoded.error());
  EXPECT_EQ(decoded->organised(), (OrganisedSize{3, 2}));
  EXPECT_EQ(decoded->channels(), (CloudChannels{.intensity = true, .ring = true, .image_position = false, .beam = true}));
  ASSERT_EQ(decoded->size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(decoded->record(i), cloud.record(i)) << i;
  EXPECT_TRUE(std::isnan(decoded->positions()[4].x_m) && std::isnan(decoded->ranges()[4]));
}

INSTANTIATE_TEST_SUITE_P(AllFormats, OrganisedFields,
                         ::testing::Values(CloudFileFormat::ply_ascii, CloudFileFormat::ply_binary,
                                           CloudFileFormat::pcd_ascii, CloudFileFormat::pcd_binary));

TEST(OrganisedFields, PcdHeaderDeclaresTheGridAndFields) {
  const auto pcd = encode_pcd(organised_scan(), PcdEncoding::ascii);
  ASSERT_TRUE(pcd);
  EXPECT_NE(pcd->find("FIELDS x y z intensity t range azimuth tilt ring\nSIZE 4 4 4 4 4 4 4 4 2\n"
                      "TYPE F F F F F F F F U\nCOUNT 1 1 1 1 1 1 1 1 1\nWIDTH 3\nHEIGHT 2\n"),
            std::string::npos)
      << *pcd;
  EXPECT_NE(pcd->find("\nnan nan nan 0 "), std::string::npos) << "the no-echo point, in PCL's spelling";
  const auto binary = encode_pcd(organised_scan(), PcdEncoding::binary);
  ASSERT_TRUE(binary);
  EXPECT_EQ(binary->size() - (binary->find("DATA binary\n") + 12), 6u * 34u);
}

TEST(OrganisedFields, PlyUsesTypesOpen3dKeepsAndPclsGridLines) {
  const auto ply = encode_ply(organised_scan(), PlyEncoding::ascii);
  ASSERT_TRUE(ply);
  EXPECT_NE(ply->find("obj_info num_cols 3\nobj_info num_rows 2\nelement vertex 6\n"), std::string::npos) << *ply;
  EXPECT_NE(ply->find("property float tilt\nproperty uint16 ring\nend_header\n"), std::string::npos) << *ply;
  EXPECT_EQ(ply->find("ushort"), std::string::npos) << "Open3D 0.16 drops a ushort property";
}

}  // namespace
}  // namespace ldoem::cloud
