#include <gtest/gtest.h>

#include "ldoem/cloud/ply.hpp"
#include "sample_clouds.hpp"

namespace ldoem::cloud {
namespace {

using testing::all_channels_cloud;
using testing::same_file_content;
using testing::three_point_cloud;

class PlyRoundTrip : public ::testing::TestWithParam<PlyEncoding> {};

TEST_P(PlyRoundTrip, AllChannels_ReadBackIdentical) {
  const PointCloud cloud = all_channels_cloud();
  const auto bytes = encode_ply(cloud, GetParam());
  ASSERT_TRUE(bytes);
  const auto decoded = decode_ply(*bytes);
  ASSERT_TRUE(decoded) << to_string(decoded.error());
  EXPECT_TRUE(same_file_content(cloud, *decoded));
}

TEST_P(PlyRoundTrip, PositionsOnly_ReadBackWithoutChannels) {
  const PointCloud cloud = three_point_cloud({});
  const auto decoded = decode_ply(encode_ply(cloud, GetParam()).value());
  ASSERT_TRUE(decoded);
  EXPECT_FALSE(decoded->channels().intensity);
  EXPECT_FALSE(decoded->channels().ring);
  EXPECT_TRUE(same_file_content(cloud, *decoded));
}

TEST_P(PlyRoundTrip, NanPosition_StaysNan) {
  PointCloud cloud;
  cloud.push_back(testing::point_at({std::numeric_limits<float>::quiet_NaN(), 1.0F, 2.0F}));
  const auto decoded = decode_ply(encode_ply(cloud, GetParam()).value());
  ASSERT_TRUE(decoded);
  EXPECT_TRUE(std::isnan(decoded->positions()[0].x_m));
}

TEST_P(PlyRoundTrip, EmptyCloud_ReadsBackEmpty) {
  const auto decoded = decode_ply(encode_ply(PointCloud{}, GetParam()).value());
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->size(), 0U);
}

TEST_P(PlyRoundTrip, EveryTruncation_IsTypedError) {
  const std::string bytes = encode_ply(all_channels_cloud(), GetParam()).value();
  for (std::size_t length = 0; length + 1 < bytes.size(); ++length) {
    const auto decoded = decode_ply(std::string_view(bytes).substr(0, length));
    ASSERT_FALSE(decoded) << "length " << length;
    EXPECT_TRUE(decoded.error() == CloudIoError::truncated_data || decoded.error() == CloudIoError::bad_magic ||
                decoded.error() == CloudIoError::malformed_header || decoded.error() == CloudIoError::malformed_number)
        << "length " << length << ": " << to_string(decoded.error());
  }
}

INSTANTIATE_TEST_SUITE_P(Encodings, PlyRoundTrip,
                         ::testing::Values(PlyEncoding::ascii, PlyEncoding::binary_little_endian));

TEST(PlyEncode, AsciiHeaderAndBody_MatchHandWrittenFile) {
  const std::string expected =
      "ply\n"
      "format ascii 1.0\n"
      "comment ldoem point cloud\n"
      "element vertex 3\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "property float intensity\n"
      "property uint16 ring\n"
      "end_header\n"
      "1 -2.5 0.125 100 0\n"
      "0.1 3.3333333 -7.75 65535 1\n"
      "1234.5677 1e-07 -0 0.5 65535\n";
  EXPECT_EQ(encode_ply(all_channels_cloud(), PlyEncoding::ascii).value(), expected);
}

TEST(PlyEncode, BinaryHeader_MatchesHandWrittenHeader) {
  const std::string expected_header =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment scan of corridor\n"
      "element vertex 3\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "end_header\n";
  const std::string bytes = encode_ply(three_point_cloud({}), PlyEncoding::binary_little_endian, "scan of corridor").value();
  EXPECT_EQ(bytes.substr(0, expected_header.size()), expected_header);
  // 3 points x 3 floats x 4 bytes after the header, nothing else.
  EXPECT_EQ(bytes.size(), expected_header.size() + 3 * 12);
}

TEST(PlyEncode, BinaryBody_IsLittleEndianBytes) {
  PointCloud cloud(CloudChannels{.intensity = true, .ring = true});
  cloud.push_back(PointRecord{{1.0F, -2.0F, 0.5F}, 3.0F, 0x0102, {}});
  const std::string bytes = encode_ply(cloud, PlyEncoding::binary_little_endian).value();
  const std::string body = bytes.substr(bytes.size() - 18);
  // 1.0f = 0x3F800000, -2.0f = 0xC0000000, 0.5f = 0x3F000000, 3.0f = 0x40400000, ring 0x0102.
  const std::string expected("\x00\x00\x80\x3F\x00\x00\x00\xC0\x00\x00\x00\x3F\x00\x00\x40\x40\x02\x01", 18);
  EXPECT_EQ(body, expected);
}

TEST(PlyEncode, CommentWithNewline_IsRejected) {
  const auto bytes = encode_ply(PointCloud{}, PlyEncoding::ascii, "two\nlines");
  ASSERT_FALSE(bytes);
  EXPECT_EQ(bytes.error(), CloudIoError::bad_comment);
}

TEST(PlyDecode, NotPly_IsBadMagic) {
  const auto decoded = decode_ply("VERSION .7\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::bad_magic);
}

TEST(PlyDecode, BigEndian_IsUnsupported) {
  const auto decoded = decode_ply("ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::unsupported_layout);
}

TEST(PlyDecode, MissingZ_IsMissingField) {
  const auto decoded = decode_ply("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::missing_field);
}

TEST(PlyDecode, HugeVertexCount_IsTruncatedWithoutAllocating) {
  const auto decoded = decode_ply(
      "ply\nformat binary_little_endian 1.0\nelement vertex 4294967295\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n0123456789ab");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::truncated_data);
}

TEST(PlyDecode, UnknownHeaderKeyword_IsMalformed) {
  const auto decoded = decode_ply("ply\nformat ascii 1.0\nelephant vertex 1\nend_header\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::malformed_header);
}

TEST(PlyDecode, BadNumber_IsMalformedNumber) {
  const auto decoded = decode_ply(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 two 3\n");
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error(), CloudIoError::malformed_number);
}

TEST(PlyDecode, OtherToolsLayout_ReadsPositionsAndSkipsExtras) {
  // Double coordinates, an extra colour property, an element before the vertices, CRLF lines.
  const auto decoded = decode_ply(
      "ply\r\nformat ascii 1.0\r\nobj_info made elsewhere\r\nelement camera 1\r\nproperty float fov\r\n"
      "element vertex 2\r\nproperty double x\r\nproperty double y\r\nproperty double z\r\n"
      "property uchar red\r\nproperty int ring\r\nelement face 0\r\nproperty list uchar int vertex_indices\r\n"
      "end_header\r\n60\r\n1.5 2.5 3.5 255 7\r\n-1 -2 -3 0 8\r\n");
  ASSERT_TRUE(decoded) << to_string(decoded.error());
  ASSERT_EQ(decoded->size(), 2U);
  EXPECT_EQ(decoded->positions()[1], (Point3f{-1.0F, -2.0F, -3.0F}));
  EXPECT_FALSE(decoded->channels().intensity);
  ASSERT_TRUE(decoded->channels().ring);
  EXPECT_EQ(decoded->rings()[1], 8);
}

}  // namespace
}  // namespace ldoem::cloud
