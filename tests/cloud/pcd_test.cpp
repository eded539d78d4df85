#include <gtest/gtest.h>

#include "ldoem/cloud/pcd.hpp"
#include "sample_clouds.hpp"

namespace ldoem::cloud {
namespace {

using testing::all_channels_cloud;
using testing::same_file_content;
using testing::three_point_cloud;

PointCloud organised_cloud() {
  PointCloud cloud(CloudChannels{.intensity = true});
  for (std::uint32_t row = 0; row < 2; ++row) {
    for (std::uint32_t column = 0; column < 3; ++column) {
      const float nan = std::numeric_limits<float>::quiet_NaN();
      const bool echo = !(row == 1 && column == 2);
      cloud.push_back(testing::point_at(echo ? Point3f{float(column), float(row), 1.0F} : Point3f{nan, nan, nan},
                                        echo ? 10.0F : 0.0F));
    }
  }
  EXPECT_TRUE(cloud.set_organised(OrganisedSize{3, 2}));
  return cloud;
}

class PcdRoundTrip : public ::testing::TestWithParam<PcdEncoding> {};

TEST_P(PcdRoundTrip, AllChannels_ReadBackIdentical) {
  const PointCloud cloud = all_channels_cloud();
  const auto decoded = decode_pcd(encode_pcd(cloud, GetParam()).value());
  ASSERT_TRUE(decoded) << to_string(decoded.error());
  EXPECT_TRUE(same_file_content(cloud, *decoded));
  EXPECT_FALSE(decoded->organised());
}

TEST_P(PcdRoundTrip, OrganisedWithNan_KeepsLayoutAndNan) {
  const PointCloud cloud = organised_cloud();
  const auto decoded = decode_pcd(encode_pcd(cloud, GetParam()).value());
  ASSERT_TRUE(decoded) << to_string(decoded.error());
  EXPECT_TRUE(same_file_content(cloud, *decoded));
  EXPECT_EQ(decoded->organised(), (OrganisedSize{3, 2}));
}

TEST_P(PcdRoundTrip, EveryTruncation_IsTypedError) {
  const std::string bytes = encode_pcd(all_channels_cloud(), GetParam()).value();
  for (std::size_t length = 0; length + 1 < bytes.size(); ++length) {
    const auto decoded = decode_pcd(std::string_view(bytes).substr(0, length));
    ASSERT_FALSE(decoded) << "length " << length;
    EXPECT_TRUE(decoded.error() == CloudIoError::truncated_data || decoded.error() == CloudIoError::bad_magic ||
                decoded.error() == CloudIoError::malformed_header || decoded.error() == CloudIoError::malformed_number)
        << "length " << length << ": " << to_string(decoded.error());
  }
}

INSTANTIATE_TEST_SUITE_P(Encodings, PcdRoundTrip, ::testing::Values(PcdEncoding::ascii, PcdEncoding::binary));

TEST(PcdEncode, AsciiFile_MatchesHandWrittenFile) {
  const std::string expected =
      "VERSION .7\n"
      "FIELDS x y z intensity ring\n"
      "SIZE 4 4 4 4 2\n"
      "TYPE F F F F U\n"
      "COUNT 1 1 1 1 1\n"
      "WIDTH 3\n"
      "HEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS 3\n"
      "DATA ascii\n"
      "1 -2.5 0.125 100 0\n"
      "0.1 3.3333333 -7.75 65535 1\n"
      "1234.5677 1e-07 -0 0.5 65535\n";
  EXPECT_EQ(encode_pcd(all_channels_cloud(), PcdEncoding::ascii).value(), expected);
}

TEST(PcdEncode, BinaryOrganised_HeaderAndExactSize) {
  const std::string expected_header =
      "VERSION .7\n"
      "FIELDS x y z intensity\n"
      "SIZE 4 4 4 4\n"
      "TYPE F F F F\n"
      "COUNT 1 1 1 1\n"
      "WIDTH 3\n"
      "HEIGHT 2\n"
      "VIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS 6\n"
      "DATA binary\n";
  const std::string bytes = encode_pcd(organised_cloud(), PcdEncoding::binary).value();
  EXPECT_EQ(bytes.substr(0, expected_header.size()), expected_header);
  EXPECT_EQ(bytes.size(), expected_header.size() + 6 * 16);
}

TEST(PcdEncode, BinaryRecords_ArePackedLittleEndian) {
  PointCloud cloud(CloudChannels{.intensity = true, .ring = true});
  cloud.push_back(PointRecord{{1.0F, -2.0F, 0.5F}, 3.0F, 0x0102, {}});
  cloud.push_back(PointRecord{{0.0F, 0.0F, 0.0F}, 0.0F, 0xA0B0, {}});
  const std::string bytes = encode_pcd(cloud, PcdEncoding::binary).value();
  // Packed 18-byte records (no padding to 20), FIELDS order.
  const std::string expected(
      "\x00\x00\x80\x3F\x00\x00\x00\xC0\x00\x00\x00\x3F\x00\x00\x40\x40\x02\x01"
      "\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\xB0\xA0",
      36);
  EXPECT_EQ(bytes.substr(bytes.size() - 36), expected);
}

TEST(PcdDecode, PointsDisagreeWithWidthTimesHeight_IsInconsistent) {
  const auto decoded = decode_pcd(
      "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\n"
      "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\nDATA ascii\n1 2 3\n4 5 6\n7 8 9\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::inconsistent_header);
}

TEST(PcdDecode, SizeListShorterThanFields_IsInconsistent) {
  const auto decoded = decode_pcd(
      "VERSION .7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::inconsistent_header);
}

TEST(PcdDecode, EntriesOutOfOrder_IsMalformed) {
  const auto decoded = decode_pcd(
      "VERSION .7\nSIZE 4 4 4\nFIELDS x y z\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::malformed_header);
}

TEST(PcdDecode, CompressedData_IsUnsupported) {
  const auto decoded = decode_pcd(
      "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary_compressed\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::unsupported_layout);
}

TEST(PcdDecode, NotPcd_IsBadMagic) {
  const auto decoded = decode_pcd("ply\nformat ascii 1.0\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::bad_magic);
}

TEST(PcdDecode, HugeBinaryCount_IsTruncatedWithoutAllocating) {
  const auto decoded = decode_pcd(
      "VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 4294967295\nHEIGHT 4294967295\nDATA binary\nabc");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::truncated_data);
}

TEST(PcdDecode, PclStyleFile_ReadsXyzAndSkipsRgbAndNormals) {
  // What PCL writes for PointXYZRGBNormal-like data: comment, "VERSION 0.7", COUNT 3, doubles.
  const auto decoded = decode_pcd(
      "# .PCD v0.7 - written by another tool\nVERSION 0.7\nFIELDS x y z rgb normal\nSIZE 8 8 8 4 4\n"
      "TYPE F F F U F\nCOUNT 1 1 1 1 3\nWIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n"
      "1.5 -2 3 4278190080 0 0 1\n");
  ASSERT_TRUE(decoded) << to_string(decoded.error());
  ASSERT_EQ(decoded->size(), 1U);
  EXPECT_EQ(decoded->positions()[0], (Point3f{1.5F, -2.0F, 3.0F}));
}

}  // namespace
}  // namespace ldoem::cloud
