// Profile telegram 0x8301 (spec 3.5).
#include "ldoem/protocol/profile.hpp"

#include "ldoem/protocol/service_codes.hpp"
#include "word_reader.hpp"

namespace ldoem::protocol {
namespace {

using namespace profile_bits;

constexpr bool has(std::uint16_t format, std::uint16_t bit) { return (format & bit) != 0; }

constexpr std::size_t count_bits(std::uint16_t format, std::initializer_list<std::uint16_t> bits) {
  std::size_t count = 0;
  for (const auto bit : bits) count += has(format, bit) ? 1 : 0;
  return count;
}

// WORDs per point and per sector block (without points), spec 3.5.
constexpr std::size_t point_words(std::uint16_t format) {
  return count_bits(format, {kDistance, kDirection, kEcho});
}
constexpr std::size_t sector_words(std::uint16_t format) {
  return count_bits(format, {kSectorNum, kDirStep, kPointNum, kTStart, kStartDir, kTEnd, kEndDir});
}
constexpr std::size_t header_words(std::uint16_t format) {
  return 3 + count_bits(format, {kProfileSent, kProfileCount, kLayerNum});  // code, format, count
}
constexpr std::size_t status_bytes(std::uint16_t format) {
  return has(format, kSensorStatus) ? StatusBlock::kSizeBytes : 0;
}

void append_if(Bytes& out, std::uint16_t format, std::uint16_t bit, std::uint16_t word) {
  if (has(format, bit)) append_word_be(out, word);
}

std::uint16_t read_if(detail::WordReader& reader, std::uint16_t format, std::uint16_t bit) {
  return has(format, bit) ? reader.word() : std::uint16_t{0};
}

void append_sector(Bytes& out, std::uint16_t format, const SectorBlock& sector) {
  append_if(out, format, kSectorNum, sector.sector_num);
  append_if(out, format, kDirStep, sector.dir_step_ticks);
  append_if(out, format, kPointNum, static_cast<std::uint16_t>(sector.points.size()));
  append_if(out, format, kTStart, sector.t_start_ms);
  append_if(out, format, kStartDir, sector.start_dir_ticks);
  for (const auto& point : sector.points) {  // interleaved per point (spec 3.5)
    append_if(out, format, kDistance, point.distance_q8_m);
    append_if(out, format, kDirection, point.direction_ticks);
    append_if(out, format, kEcho, point.echo);
  }
  append_if(out, format, kTEnd, sector.t_end_ms);
  append_if(out, format, kEndDir, sector.end_dir_ticks);
}

// Without POINTNUM, a single sector's count follows from what is left after its fixed fields.
base::Expected<std::size_t, DecodeError> implied_point_count(std::uint16_t format, std::size_t remaining_bytes) {
  const std::size_t fixed_bytes = 2 * sector_words(format) + status_bytes(format);
  if (remaining_bytes < fixed_bytes) return base::Unexpected(DecodeError::truncated);
  const std::size_t point_bytes = 2 * point_words(format);
  const std::size_t left = remaining_bytes - fixed_bytes;
  if (point_bytes == 0) {
    if (left != 0) return base::Unexpected(DecodeError::bad_length);
    return std::size_t{0};
  }
  if (left % point_bytes != 0) return base::Unexpected(DecodeError::bad_length);
  const std::size_t count = left / point_bytes;
  if (count > kMaxPointsPerSector) return base::Unexpected(DecodeError::out_of_range);
  return count;
}

base::Expected<SectorBlock, DecodeError> read_sector(detail::WordReader& reader, std::uint16_t format,
                                               std::size_t sector_count) {
  const std::size_t fixed_bytes = 2 * sector_words(format);
  SectorBlock sector;
  std::size_t count = 0;
  if (!has(format, kPointNum)) {
    if (sector_count > 1) return base::Unexpected(DecodeError::bad_length);
    auto implied = implied_point_count(format, reader.remaining_bytes());
    if (!implied) return base::Unexpected(implied.error());
    count = *implied;
  } else if (reader.remaining_bytes() < fixed_bytes) {
    return base::Unexpected(DecodeError::truncated);
  }
  sector.sector_num = read_if(reader, format, kSectorNum);
  sector.dir_step_ticks = read_if(reader, format, kDirStep);
  if (has(format, kPointNum)) {
    count = reader.word();
    if (count > kMaxPointsPerSector) return base::Unexpected(DecodeError::out_of_range);
  }
  sector.t_start_ms = read_if(reader, format, kTStart);
  sector.start_dir_ticks = read_if(reader, format, kStartDir);
  // Allocation guard: the points (and the closing fields) must be in the payload already.
  const std::size_t closing_bytes = 2 * count_bits(format, {kTEnd, kEndDir});
  if (reader.remaining_bytes() < count * 2 * point_words(format) + closing_bytes) {
    return base::Unexpected(DecodeError::truncated);
  }
  sector.points.resize(count);
  for (auto& point : sector.points) {
    point.distance_q8_m = read_if(reader, format, kDistance);
    point.direction_ticks = read_if(reader, format, kDirection);
    point.echo = read_if(reader, format, kEcho);
  }
  sector.t_end_ms = read_if(reader, format, kTEnd);
  sector.end_dir_ticks = read_if(reader, format, kEndDir);
  return sector;
}

}  // namespace

std::size_t profile_payload_size(std::uint16_t format, std::span<const std::size_t> points_per_sector) {
  std::size_t size = 2 * header_words(format) + status_bytes(format);
  for (const auto points : points_per_sector) {
    size += 2 * sector_words(format) + 2 * points * point_words(format);
  }
  return size;
}

Bytes encode_profile(const Profile& profile) {
  const std::uint16_t format = profile.format;
  Bytes out;
  std::vector<std::size_t> counts;
  counts.reserve(profile.sectors.size());
  for (const auto& sector : profile.sectors) counts.push_back(sector.points.size());
  out.reserve(profile_payload_size(format, counts));
  append_word_be(out, response_code(Service::get_profile));
  append_word_be(out, format);
  append_word_be(out, static_cast<std::uint16_t>(profile.sectors.size()));
  append_if(out, format, kProfileSent, profile.profile_sent);
  append_if(out, format, kProfileCount, profile.profile_count);
  append_if(out, format, kLayerNum, profile.layer);
  for (const auto& sector : profile.sectors) append_sector(out, format, sector);
  if (has(format, kSensorStatus)) append_status_block(out, profile.status);
  return out;
}

base::Expected<Profile, DecodeError> decode_profile(ByteView payload) {
  if (payload.size() < 6) return base::Unexpected(DecodeError::truncated);
  if (payload.size() % 2 != 0) return base::Unexpected(DecodeError::bad_length);
  detail::WordReader reader(payload);
  if (reader.word() != response_code(Service::get_profile)) return base::Unexpected(DecodeError::unknown_service);
  Profile profile;
  profile.format = reader.word();
  const std::uint16_t format = profile.format;
  const std::size_t sector_count = reader.word();
  if (sector_count > kMaxSectorBlocks) return base::Unexpected(DecodeError::out_of_range);
  if (reader.remaining_bytes() < 2 * (header_words(format) - 3)) return base::Unexpected(DecodeError::truncated);
  profile.profile_sent = read_if(reader, format, kProfileSent);
  profile.profile_count = read_if(reader, format, kProfileCount);
  profile.layer = read_if(reader, format, kLayerNum);
  profile.sectors.reserve(sector_count);
  for (std::size_t i = 0; i < sector_count; ++i) {
    auto sector = read_sector(reader, format, sector_count);
    if (!sector) return base::Unexpected(sector.error());
    profile.sectors.push_back(std::move(*sector));
  }
  if (reader.remaining_bytes() < status_bytes(format)) return base::Unexpected(DecodeError::truncated);
  if (has(format, kSensorStatus)) {
    profile.status = read_status_block(payload, reader.offset());
    reader.take(StatusBlock::kSizeBytes);
  }
  if (reader.remaining_bytes() != 0) return base::Unexpected(DecodeError::bad_length);
  return profile;
}

}  // namespace ldoem::protocol
