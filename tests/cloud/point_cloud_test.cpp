#include <gtest/gtest.h>

#include "ldoem/cloud/cloud_file.hpp"
#include "sample_clouds.hpp"

namespace ldoem::cloud {
namespace {

TEST(PointCloud, AbsentChannels_HaveEmptySpansAndReadZero) {
  PointCloud cloud(CloudChannels{.intensity = true});
  cloud.push_back(PointRecord{{1, 2, 3}, 5.0F, 7, {8, 9}});
  EXPECT_EQ(cloud.intensities().size(), 1U);
  EXPECT_TRUE(cloud.rings().empty());
  EXPECT_TRUE(cloud.image_positions().empty());
  EXPECT_EQ(cloud.record(0).ring, 0);
  EXPECT_EQ(cloud.record(0).intensity, 5.0F);
}

TEST(PointCloud, SetOrganisedWrongSize_IsRefused) {
  PointCloud cloud;
  for (int i = 0; i < 6; ++i) cloud.push_back(PointRecord{});
  EXPECT_FALSE(cloud.set_organised(OrganisedSize{4, 2}));
  EXPECT_FALSE(cloud.set_organised(OrganisedSize{0, 6}));
  EXPECT_FALSE(cloud.organised());
  EXPECT_EQ(cloud.layout(), (OrganisedSize{6, 1}));
  EXPECT_TRUE(cloud.set_organised(OrganisedSize{3, 2}));
  EXPECT_EQ(cloud.layout(), (OrganisedSize{3, 2}));
}

TEST(PointCloud, PushAfterOrganising_MakesItUnorganised) {
  PointCloud cloud;
  cloud.push_back(PointRecord{});
  ASSERT_TRUE(cloud.set_organised(OrganisedSize{1, 1}));
  cloud.push_back(PointRecord{});
  EXPECT_FALSE(cloud.organised());
}

TEST(CloudFile, FormatNames_RoundTrip) {
  for (CloudFileFormat format : {CloudFileFormat::ply_ascii, CloudFileFormat::ply_binary,
                                 CloudFileFormat::pcd_ascii, CloudFileFormat::pcd_binary}) {
    EXPECT_EQ(parse_cloud_file_format(to_string(format)), format);
  }
  EXPECT_FALSE(parse_cloud_file_format("xyz"));
}

TEST(CloudFile, WriteThenRead_AllFourFormats) {
  const PointCloud cloud = testing::all_channels_cloud();
  const std::filesystem::path directory = ::testing::TempDir();
  for (CloudFileFormat format : {CloudFileFormat::ply_ascii, CloudFileFormat::ply_binary,
                                 CloudFileFormat::pcd_ascii, CloudFileFormat::pcd_binary}) {
    const std::filesystem::path path = directory / ("cloud-" + std::string(to_string(format)));
    const auto written = write_cloud_file(path, cloud, format);
    ASSERT_TRUE(written);
    EXPECT_EQ(*written, std::filesystem::file_size(path));
    const auto read = read_cloud_file(path);
    ASSERT_TRUE(read) << to_string(read.error());
    EXPECT_TRUE(testing::same_file_content(cloud, *read)) << to_string(format);
  }
}

TEST(CloudFile, MissingFile_IsCannotOpen) {
  const auto read = read_cloud_file("/nonexistent/dir/cloud.ply");
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error(), CloudIoError::cannot_open_file);
}

}  // namespace
}  // namespace ldoem::cloud
