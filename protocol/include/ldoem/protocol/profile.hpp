// The profile telegram 0x8301 (spec 3.5, D3): one revolution, sector blocks with interleaved
// per-point fields, each field present only if its bit is set in PROFILEFORMAT.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ldoem/protocol/bytes.hpp"
#include "ldoem/protocol/errors.hpp"
#include "ldoem/base/expected.hpp"
#include "ldoem/protocol/status.hpp"

namespace ldoem::protocol {

// D3: TCP and serial telegrams carry at most this many payload bytes (ISO-TP has no limit).
inline constexpr std::size_t kMaxTelegramPayload = 5816;

// Spec 3.5: the sector numbers are 0..7, so a profile has at most 8 sector blocks; and at most
// 2881 points per sector (360 deg / 0.125 deg + 1, S1's constant).
inline constexpr std::size_t kMaxSectorBlocks = 8;
inline constexpr std::size_t kMaxPointsPerSector = 2881;

// PROFILEFORMAT bits, spec 3.5 table (bit k names field k of the telegram).
namespace profile_bits {
inline constexpr std::uint16_t kProfileSent = 1u << 0;
inline constexpr std::uint16_t kProfileCount = 1u << 1;
inline constexpr std::uint16_t kLayerNum = 1u << 2;
inline constexpr std::uint16_t kSectorNum = 1u << 3;
inline constexpr std::uint16_t kDirStep = 1u << 4;
inline constexpr std::uint16_t kPointNum = 1u << 5;
inline constexpr std::uint16_t kTStart = 1u << 6;
inline constexpr std::uint16_t kStartDir = 1u << 7;
inline constexpr std::uint16_t kDistance = 1u << 8;
inline constexpr std::uint16_t kDirection = 1u << 9;
inline constexpr std::uint16_t kEcho = 1u << 10;
inline constexpr std::uint16_t kTEnd = 1u << 11;
inline constexpr std::uint16_t kEndDir = 1u << 12;
inline constexpr std::uint16_t kSensorStatus = 1u << 13;
// Bits 14 and 15 have no published meaning; they are echoed and add no field.
inline constexpr std::uint16_t kAllFields = 0x3FFF;
}  // namespace profile_bits

// S1's formats and S2's serial formats (spec 3.5).
inline constexpr std::uint16_t kFormatRange = 0x39FF;
inline constexpr std::uint16_t kFormatRangeEcho = 0x3DFF;

struct ProfilePoint {
  std::uint16_t distance_q8_m = 0;    // metres * 256 (spec 2.3); 0 = no echo (D3)
  std::uint16_t direction_ticks = 0;  // 1/16 degree
  std::uint16_t echo = 0;             // raw amplitude
  bool operator==(const ProfilePoint&) const = default;
};

struct SectorBlock {
  std::uint16_t sector_num = 0;
  std::uint16_t dir_step_ticks = 0;
  std::uint16_t t_start_ms = 0;
  std::uint16_t start_dir_ticks = 0;
  std::vector<ProfilePoint> points;  // POINTNUM = points.size()
  std::uint16_t t_end_ms = 0;
  std::uint16_t end_dir_ticks = 0;
  bool operator==(const SectorBlock&) const = default;
};

// A field whose bit is clear in `format` is not encoded and decodes as 0 (points keep their
// count when POINTNUM is present but no point field is).
struct Profile {
  std::uint16_t format = kFormatRange;
  std::uint16_t profile_sent = 0;   // D3: counts from 1 after each GET_PROFILE
  std::uint16_t profile_count = 0;  // D3: revolutions since power-up, from 1
  std::uint16_t layer = 0;          // always 0 on the LD
  std::vector<SectorBlock> sectors;
  StatusBlock status;  // SENSTAT
  bool operator==(const Profile&) const = default;
};

// Spec 3.5 size formula: 6 + 2([0]+[1]+[2]) + sum over sectors of
// (2([3]+[4]+[5]+[6]+[7]+[11]+[12]) + 2 N_s ([8]+[9]+[10])) + 4 [13].
std::size_t profile_payload_size(std::uint16_t format,
                                 std::span<const std::size_t> points_per_sector);

// Writes exactly the fields `format` asks for, in the spec 3.5 order. The result may exceed
// kMaxTelegramPayload (fine on ISO-TP); TCP/serial senders check profile_payload_size first.
// A format without POINTNUM and more than one sector encodes, but cannot be decoded.
Bytes encode_profile(const Profile& profile);

// Decodes a whole 0x8301 payload. Without POINTNUM (S2's 0x0700 / 0x0300) the point count of
// a single sector follows from the length; several sectors without POINTNUM is bad_length.
// Never reserves more than the payload can hold (SECTORCOUNT <= 8, POINTNUM <= 2881 and,
// when point fields are present, covered by the remaining bytes).
base::Expected<Profile, DecodeError> decode_profile(ByteView payload);

}  // namespace ldoem::protocol
