// Profile telegram (spec 3.5): size formula, S2's formats without POINTNUM, allocation bounds.
#include <random>

#include "ldoem/protocol/messages.hpp"
#include "ldoem/protocol/profile.hpp"
#include "test_support.hpp"

namespace ldoem::protocol {
namespace {

using test::hex;

TEST(ProfilePayloadSize, SpecExamples) {
  const std::size_t one_sector[] = {100};
  EXPECT_EQ(profile_payload_size(kFormatRange, one_sector), 30u + 2 * 100);      // 30 + 2N
  EXPECT_EQ(profile_payload_size(kFormatRangeEcho, one_sector), 30u + 4 * 100);  // 30 + 4N
  const std::size_t finest[] = {kMaxPointsPerSector};
  // Spec 4.1: a single-sector 0.125 deg range profile is 5792 bytes and fits; with echo not.
  EXPECT_EQ(profile_payload_size(kFormatRange, finest), 5792u);
  EXPECT_LE(profile_payload_size(kFormatRange, finest), kMaxTelegramPayload);
  EXPECT_GT(profile_payload_size(kFormatRangeEcho, finest), kMaxTelegramPayload);
  EXPECT_EQ(profile_payload_size(0x0000, {}), 6u);
}

TEST(ProfilePayloadSize, MatchesEncoderForEveryFormatBit) {
  for (unsigned bit = 0; bit < 16; ++bit) {
    Profile profile;
    profile.format = static_cast<std::uint16_t>(1u << bit);
    profile.sectors.resize(2);
    profile.sectors[0].points.resize(3);
    profile.sectors[1].points.resize(5);
    const std::size_t counts[] = {3, 5};
    EXPECT_EQ(encode_profile(profile).size(), profile_payload_size(profile.format, counts)) << "bit " << bit;
  }
}

TEST(DecodeProfile, S2Format0700_PointCountFromLength) {
  // distance + direction + echo per point, no POINTNUM: 2 points.
  const Bytes payload = hex("83 01 07 00 00 01  01 00 00 10 00 C8  02 80 00 18 00 50");
  const auto decoded = decode_profile(payload);
  ASSERT_TRUE(decoded.has_value()) << describe(decoded.error());
  ASSERT_EQ(decoded->sectors.size(), 1u);
  EXPECT_EQ(decoded->sectors[0].points,
            (std::vector<ProfilePoint>{{0x0100, 0x0010, 200}, {0x0280, 0x0018, 80}}));
  EXPECT_EQ(encode_profile(*decoded), payload);
}

TEST(DecodeProfile, S2Format0300_PointCountFromLength) {
  const Bytes payload = hex("83 01 03 00 00 01  01 00 00 10  02 80 00 18  00 00 00 20");
  const auto decoded = decode_profile(payload);
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(decoded->sectors[0].points.size(), 3u);
  EXPECT_EQ(encode_profile(*decoded), payload);
}

struct BadProfile {
  const char* title;
  const char* payload_hex;
  DecodeError expected;
};

class DecodeProfileFailure : public ::testing::TestWithParam<BadProfile> {};

TEST_P(DecodeProfileFailure, NamesTheProblem) {
  const auto decoded = decode_profile(hex(GetParam().payload_hex));
  ASSERT_FALSE(decoded.has_value()) << GetParam().title;
  EXPECT_EQ(decoded.error(), GetParam().expected) << GetParam().title;
}

INSTANTIATE_TEST_SUITE_P(
    Profiles, DecodeProfileFailure,
    ::testing::Values(
        BadProfile{"too short", "83 01 39 FF", DecodeError::truncated},
        BadProfile{"odd length", "83 01 00 00 00 00 00", DecodeError::bad_length},
        BadProfile{"not a profile", "83 02 00 00 00 00", DecodeError::unknown_service},
        BadProfile{"two sectors without POINTNUM", "83 01 07 00 00 02 01 00 00 10 00 C8", DecodeError::bad_length},
        BadProfile{"partial point without POINTNUM", "83 01 07 00 00 01 01 00 00 10", DecodeError::bad_length},
        BadProfile{"nine sector blocks", "83 01 00 00 00 09", DecodeError::out_of_range},
        BadProfile{"POINTNUM above 2881", "83 01 00 20 00 01 0B 42", DecodeError::out_of_range},
        // POINTNUM 2881 with no point bytes: refused before any allocation.
        BadProfile{"POINTNUM not covered by bytes", "83 01 01 20 00 01 0B 41 01 00", DecodeError::truncated},
        BadProfile{"missing header fields", "83 01 00 07 00 00 00 01", DecodeError::truncated},
        BadProfile{"missing SENSTAT", "83 01 20 00 00 00 00 00", DecodeError::truncated},
        BadProfile{"surplus bytes", "83 01 00 00 00 00 00 00", DecodeError::bad_length}));

TEST(DecodeProfile, PointNumWithoutPointFields_KeepsCount) {
  const Bytes payload = hex("83 01 00 20 00 01 00 04");  // POINTNUM only: 4 points, no fields
  const auto decoded = decode_profile(payload);
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(decoded->sectors[0].points.size(), 4u);
  EXPECT_EQ(encode_profile(*decoded), payload);
}

TEST(DecodeProfile, Bits14And15_AreEchoedAndAddNoField) {
  const Bytes payload = hex("83 01 C0 01 00 00 00 07");
  const auto decoded = decode_profile(payload);
  ASSERT_TRUE(decoded.has_value());
  EXPECT_EQ(decoded->format, 0xC001);
  EXPECT_EQ(decoded->profile_sent, 7);
}

// Random profiles over random formats: decode(encode(p)) == p.
TEST(ProfileRoundTrip, RandomProfiles_SurviveEncodeDecode) {
  std::mt19937 rng(20240601);
  std::uniform_int_distribution<unsigned> word(0, 0xFFFF);
  auto w = [&] { return static_cast<std::uint16_t>(word(rng)); };
  for (int trial = 0; trial < 500; ++trial) {
    Profile profile;
    profile.format = w();
    using namespace profile_bits;
    auto keep = [&](std::uint16_t bit, std::uint16_t value) {
      return (profile.format & bit) ? value : std::uint16_t{0};
    };
    const bool has_point_num = profile.format & kPointNum;
    const bool has_point_fields = profile.format & (kDistance | kDirection | kEcho);
    std::size_t sectors = std::uniform_int_distribution<std::size_t>(0, has_point_num ? 8 : 1)(rng);
    profile.profile_sent = keep(kProfileSent, w());
    profile.profile_count = keep(kProfileCount, w());
    profile.layer = keep(kLayerNum, w());
    for (std::size_t s = 0; s < sectors; ++s) {
      SectorBlock block;
      block.sector_num = keep(kSectorNum, w());
      block.dir_step_ticks = keep(kDirStep, w());
      block.t_start_ms = keep(kTStart, w());
      block.start_dir_ticks = keep(kStartDir, w());
      const std::size_t points =
          (has_point_num || has_point_fields) ? std::uniform_int_distribution<std::size_t>(0, 40)(rng) : 0;
      for (std::size_t p = 0; p < points; ++p) {
        block.points.push_back({keep(kDistance, w()), keep(kDirection, w()), keep(kEcho, w())});
      }
      block.t_end_ms = keep(kTEnd, w());
      block.end_dir_ticks = keep(kEndDir, w());
      profile.sectors.push_back(block);
    }
    if (profile.format & kSensorStatus) {
      profile.status = StatusBlock{{static_cast<std::uint8_t>(w()), 0, 1}, StatusByte::from_byte(static_cast<std::uint8_t>(w()))};
    }
    const Bytes payload = encode_profile(profile);
    const auto decoded = decode_profile(payload);
    ASSERT_TRUE(decoded.has_value()) << "trial " << trial << ": " << describe(decoded.error());
    EXPECT_EQ(*decoded, profile) << "trial " << trial << " format " << std::hex << profile.format;
    const auto as_response = decode_response(payload);
    ASSERT_TRUE(as_response.has_value());
    EXPECT_EQ(encode_response(*as_response), payload);
  }
}

}  // namespace
}  // namespace ldoem::protocol
