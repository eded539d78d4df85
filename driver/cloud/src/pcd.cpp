// PCD v0.7 writer and reader. Format facts: the Point Cloud Library's PCD file format
// description (header entries and their order, field TYPE/SIZE letters, packed binary data).
#include "ldoem/cloud/pcd.hpp"

#include <array>
#include <limits>
#include <optional>
#include <vector>

#include "codec_support.hpp"
#include "record_writer.hpp"
#include "record_reader.hpp"

namespace ldoem::cloud {
namespace {

using detail::FieldSpec;
using detail::ScalarType;

std::string pcd_header(const PointCloud& cloud, PcdEncoding encoding) {
  const std::vector<detail::FieldDeclaration> fields = detail::written_fields(cloud.channels());
  const OrganisedSize layout = cloud.layout();
  std::string header = "VERSION .7\nFIELDS";
  for (const auto& field : fields) (header += ' ') += field.name;
  header += "\nSIZE";
  for (const auto& field : fields) header += field.is_ring ? " 2" : " 4";
  header += "\nTYPE";
  for (const auto& field : fields) header += field.is_ring ? " U" : " F";
  header += "\nCOUNT";
  for (std::size_t i = 0; i < fields.size(); ++i) header += " 1";
  header += "\nWIDTH ";
  detail::append_uint_text(header, layout.width);
  header += "\nHEIGHT ";
  detail::append_uint_text(header, layout.height);
  // Identity pose: positions are already in the frame the caller wants.
  header += "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS ";
  detail::append_uint_text(header, cloud.size());
  header += encoding == PcdEncoding::ascii ? "\nDATA ascii\n" : "\nDATA binary\n";
  return header;
}

// Header entries in the order PCD v0.7 mandates.
enum class Entry : std::uint8_t { version, fields, size, type, count, width, height, viewpoint, points, data };
constexpr std::array<std::string_view, 10> entry_names = {
    "VERSION", "FIELDS", "SIZE", "TYPE", "COUNT", "WIDTH", "HEIGHT", "VIEWPOINT", "POINTS", "DATA"};

std::optional<Entry> entry_of(std::string_view keyword) {
  const std::optional<std::size_t> index = detail::find_name(entry_names, keyword);
  if (!index) return std::nullopt;
  return static_cast<Entry>(*index);
}

std::optional<ScalarType> pcd_scalar_type(std::string_view letter, std::uint64_t size) {
  if (letter == "F" && size == 4) return ScalarType::f32;
  if (letter == "F" && size == 8) return ScalarType::f64;
  if (letter == "U" && size == 1) return ScalarType::u8;
  if (letter == "U" && size == 2) return ScalarType::u16;
  if (letter == "U" && size == 4) return ScalarType::u32;
  if (letter == "U" && size == 8) return ScalarType::u64;
  if (letter == "I" && size == 1) return ScalarType::i8;
  if (letter == "I" && size == 2) return ScalarType::i16;
  if (letter == "I" && size == 4) return ScalarType::i32;
  if (letter == "I" && size == 8) return ScalarType::i64;
  return std::nullopt;
}

// The raw header, entry by entry, before the entries are checked against each other.
struct RawPcdHeader {
  std::vector<std::string_view> fields;
  std::vector<std::string_view> sizes;
  std::vector<std::string_view> types;
  std::vector<std::string_view> counts;
  std::uint64_t width = 0;
  std::uint64_t height = 0;
  std::optional<std::uint64_t> points;
  std::string_view data;
  std::size_t body_offset = 0;
};

std::vector<std::string_view> rest_tokens(detail::TokenCursor& tokens) {
  std::vector<std::string_view> values;
  while (const std::optional<std::string_view> token = tokens.next()) values.push_back(*token);
  return values;
}

std::optional<CloudIoError> store_entry(Entry entry, std::vector<std::string_view> values,
                                        RawPcdHeader& header) {
  const auto single_number = [&values]() -> std::optional<std::uint64_t> {
    if (values.size() != 1) return std::nullopt;
    return detail::parse_unsigned(values.front());
  };
  switch (entry) {
    case Entry::version:
      if (values.size() != 1 || (values[0] != ".7" && values[0] != "0.7")) {
        return CloudIoError::unsupported_layout;
      }
      return std::nullopt;
    case Entry::fields: header.fields = std::move(values); return std::nullopt;
    case Entry::size: header.sizes = std::move(values); return std::nullopt;
    case Entry::type: header.types = std::move(values); return std::nullopt;
    case Entry::count: header.counts = std::move(values); return std::nullopt;
    case Entry::width:
    case Entry::height:
    case Entry::points: {
      const std::optional<std::uint64_t> number = single_number();
      if (!number) return CloudIoError::malformed_header;
      if (entry == Entry::width) header.width = *number;
      if (entry == Entry::height) header.height = *number;
      if (entry == Entry::points) header.points = *number;
      return std::nullopt;
    }
    case Entry::viewpoint:
      if (values.size() != 7) return CloudIoError::malformed_header;
      for (std::string_view value : values) {
        if (!detail::parse_double(value)) return CloudIoError::malformed_header;
      }
      return std::nullopt;
    case Entry::data:
      if (values.size() != 1) return CloudIoError::malformed_header;
      header.data = values.front();
      return std::nullopt;
  }
  return CloudIoError::malformed_header;
}

Expected<RawPcdHeader, CloudIoError> parse_raw_header(std::string_view file_bytes) {
  RawPcdHeader header;
  detail::LineCursor lines(file_bytes);
  std::optional<Entry> previous;
  bool seen_width = false;
  bool seen_height = false;
  while (true) {
    const std::optional<std::string_view> line = lines.next_line();
    if (!line) {
      return Unexpected(previous ? CloudIoError::truncated_data : CloudIoError::bad_magic);
    }
    if (line->empty() || line->front() == '#') continue;
    detail::TokenCursor tokens(*line);
    const std::optional<Entry> entry = entry_of(tokens.next().value_or(""));
    if (!previous && entry != Entry::version) return Unexpected(CloudIoError::bad_magic);
    if (!entry || (previous && *entry <= *previous)) return Unexpected(CloudIoError::malformed_header);
    if (const std::optional<CloudIoError> error = store_entry(*entry, rest_tokens(tokens), header)) {
      return Unexpected(*error);
    }
    seen_width = seen_width || entry == Entry::width;
    seen_height = seen_height || entry == Entry::height;
    previous = entry;
    if (*entry == Entry::data) break;
  }
  if (header.fields.empty() || header.sizes.empty() || header.types.empty() || !seen_width ||
      !seen_height) {
    return Unexpected(CloudIoError::malformed_header);
  }
  header.body_offset = lines.offset();
  return header;
}

Expected<std::vector<FieldSpec>, CloudIoError> field_specs(const RawPcdHeader& header) {
  const std::size_t field_count = header.fields.size();
  if (header.sizes.size() != field_count || header.types.size() != field_count ||
      (!header.counts.empty() && header.counts.size() != field_count)) {
    return Unexpected(CloudIoError::inconsistent_header);
  }
  std::vector<FieldSpec> specs;
  for (std::size_t index = 0; index < field_count; ++index) {
    const std::optional<std::uint64_t> size = detail::parse_unsigned(header.sizes[index]);
    const std::optional<ScalarType> type =
        size ? pcd_scalar_type(header.types[index], *size) : std::nullopt;
    const std::optional<std::uint64_t> count =
        header.counts.empty() ? std::optional<std::uint64_t>(1) : detail::parse_unsigned(header.counts[index]);
    if (!type || !count || *count == 0 || *count > 65535) {
      return Unexpected(CloudIoError::malformed_header);
    }
    specs.push_back(FieldSpec{std::string(header.fields[index]), *type, static_cast<std::uint32_t>(*count)});
  }
  return specs;
}

}  // namespace

Expected<std::string, CloudIoError> encode_pcd(const PointCloud& cloud, PcdEncoding encoding) {
  if (cloud.size() > std::numeric_limits<std::uint32_t>::max()) {
    return Unexpected(CloudIoError::too_many_points);
  }
  std::string file = pcd_header(cloud, encoding);
  if (encoding == PcdEncoding::ascii) {
    detail::append_ascii_records(file, cloud);
  } else {
    detail::append_binary_records(file, cloud);
  }
  return file;
}

Expected<PointCloud, CloudIoError> decode_pcd(std::string_view file_bytes) {
  const Expected<RawPcdHeader, CloudIoError> header = parse_raw_header(file_bytes);
  if (!header) return Unexpected(header.error());
  const Expected<std::vector<FieldSpec>, CloudIoError> specs = field_specs(*header);
  if (!specs) return Unexpected(specs.error());
  // Both are at most 2^32 - 1 in any file PCL writes, so the product cannot overflow.
  if (header->width > std::numeric_limits<std::uint32_t>::max() ||
      header->height > std::numeric_limits<std::uint32_t>::max()) {
    return Unexpected(CloudIoError::inconsistent_header);
  }
  const std::uint64_t cells = header->width * header->height;
  const std::uint64_t point_count = header->points.value_or(cells);
  if (point_count != cells) return Unexpected(CloudIoError::inconsistent_header);

  const std::string_view body = file_bytes.substr(header->body_offset);
  Expected<PointCloud, CloudIoError> cloud = Unexpected(CloudIoError::unsupported_layout);
  if (header->data == "ascii") {
    cloud = detail::read_ascii_records(body, *specs, point_count);
  } else if (header->data == "binary") {
    cloud = detail::read_binary_records(body, *specs, point_count);
  } else if (header->data != "binary_compressed") {
    return Unexpected(CloudIoError::malformed_header);
  }
  if (cloud && header->height > 1) {
    const bool organised = cloud->set_organised(OrganisedSize{static_cast<std::uint32_t>(header->width),
                                                              static_cast<std::uint32_t>(header->height)});
    if (!organised) return Unexpected(CloudIoError::inconsistent_header);
  }
  return cloud;
}

}  // namespace ldoem::cloud
