#include "record_reader.hpp"

#include <algorithm>
#include <array>
#include <string_view>
#include <optional>

namespace ldoem::cloud::detail {
namespace {

constexpr std::array<std::string_view, 4> kBeamFields{"t", "range", "azimuth", "tilt"};

// Where the channels ldoem knows sit in a record: index into the flat value list.
struct ChannelSlots {
  std::size_t x = 0;
  std::size_t y = 0;
  std::size_t z = 0;
  std::optional<std::size_t> intensity;
  std::optional<std::size_t> ring;
  // t, range, azimuth, tilt: the beam channel, only when all four are there.
  std::array<std::optional<std::size_t>, 4> beam;
  std::size_t values_per_record = 0;
};

std::optional<ChannelSlots> locate_channels(const std::vector<FieldSpec>& fields) {
  ChannelSlots slots;
  std::optional<std::size_t> x;
  std::optional<std::size_t> y;
  std::optional<std::size_t> z;
  for (const FieldSpec& field : fields) {
    const std::size_t slot = slots.values_per_record;
    if (field.count == 1) {
      if (field.name == "x") x = slot;
      if (field.name == "y") y = slot;
      if (field.name == "z") z = slot;
      if (field.name == "intensity") slots.intensity = slot;
      if (field.name == "ring") slots.ring = slot;
      if (const std::optional<std::size_t> beam_field = find_name(kBeamFields, field.name)) {
        slots.beam[*beam_field] = slot;
      }
    }
    slots.values_per_record += field.count;
  }
  if (!x || !y || !z) return std::nullopt;
  slots.x = *x;
  slots.y = *y;
  slots.z = *z;
  return slots;
}

bool has_beam(const ChannelSlots& slots) {
  return std::all_of(slots.beam.begin(), slots.beam.end(), [](const auto& slot) { return slot.has_value(); });
}

PointCloud make_cloud(const ChannelSlots& slots) {
  CloudChannels channels;
  channels.intensity = slots.intensity.has_value();
  channels.ring = slots.ring.has_value();
  channels.beam = has_beam(slots);
  return PointCloud(channels);
}

PointRecord record_from_values(const ChannelSlots& slots, const std::vector<double>& values) {
  PointRecord record;
  record.position = Point3f{static_cast<float>(values[slots.x]), static_cast<float>(values[slots.y]),
                            static_cast<float>(values[slots.z])};
  if (slots.intensity) record.intensity = static_cast<float>(values[*slots.intensity]);
  if (slots.ring) record.ring = to_ring(values[*slots.ring]);
  if (has_beam(slots)) {
    record.time_s = static_cast<float>(values[*slots.beam[0]]);
    record.range_m = static_cast<float>(values[*slots.beam[1]]);
    record.azimuth_rad = static_cast<float>(values[*slots.beam[2]]);
    record.tilt_rad = static_cast<float>(values[*slots.beam[3]]);
  }
  return record;
}

}  // namespace

Expected<PointCloud, CloudIoError> read_binary_records(std::string_view body,
                                                       const std::vector<FieldSpec>& fields,
                                                       std::uint64_t point_count) {
  const std::optional<ChannelSlots> slots = locate_channels(fields);
  if (!slots) return Unexpected(CloudIoError::missing_field);
  std::size_t record_size = 0;
  for (const FieldSpec& field : fields) record_size += scalar_size(field.type) * field.count;
  // Division, not multiplication: a hostile count must not overflow into a small product.
  if (point_count > body.size() / record_size) return Unexpected(CloudIoError::truncated_data);

  PointCloud cloud = make_cloud(*slots);
  cloud.reserve(static_cast<std::size_t>(point_count));
  std::vector<double> values(slots->values_per_record);
  std::size_t offset = 0;
  for (std::uint64_t point = 0; point < point_count; ++point) {
    std::size_t value_index = 0;
    for (const FieldSpec& field : fields) {
      for (std::uint32_t element = 0; element < field.count; ++element) {
        values[value_index++] = read_scalar_le(body, offset, field.type);
        offset += scalar_size(field.type);
      }
    }
    cloud.push_back(record_from_values(*slots, values));
  }
  return cloud;
}

Expected<PointCloud, CloudIoError> read_ascii_records(std::string_view body,
                                                      const std::vector<FieldSpec>& fields,
                                                      std::uint64_t point_count) {
  const std::optional<ChannelSlots> slots = locate_channels(fields);
  if (!slots) return Unexpected(CloudIoError::missing_field);
  // Every value takes at least one character and one separator: a count the body cannot hold
  // is truncation, found before any allocation.
  const std::uint64_t min_bytes_per_point = 2 * slots->values_per_record - 1;
  if (point_count > (body.size() + 1) / min_bytes_per_point) {
    return Unexpected(CloudIoError::truncated_data);
  }

  PointCloud cloud = make_cloud(*slots);
  cloud.reserve(static_cast<std::size_t>(point_count));
  std::vector<double> values(slots->values_per_record);
  TokenCursor tokens(body);
  for (std::uint64_t point = 0; point < point_count; ++point) {
    for (double& value : values) {
      const std::optional<std::string_view> token = tokens.next();
      if (!token) return Unexpected(CloudIoError::truncated_data);
      const std::optional<double> parsed = parse_double(*token);
      if (!parsed) return Unexpected(CloudIoError::malformed_number);
      value = *parsed;
    }
    cloud.push_back(record_from_values(*slots, values));
  }
  // A file cut inside its last number still parses; both formats end every record with a line
  // break, so a value that runs to the end of the file is taken as cut.
  if (point_count > 0 && tokens.at_end()) return Unexpected(CloudIoError::truncated_data);
  return cloud;
}

}  // namespace ldoem::cloud::detail
