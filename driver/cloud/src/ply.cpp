// PLY writer and reader. Format facts: Greg Turk's PLY description (header keywords ply,
// format, comment, obj_info, element, property, end_header; scalar type names old and new).
#include "ldoem/cloud/ply.hpp"

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

// Open3D's tensor reader (o3d.t.io.read_point_cloud) keeps a property only when its type is
// one it maps to a tensor dtype: it drops "ushort" (0.16) but keeps the sized name "uint16",
// which PCL's reader and CloudCompare take too.
constexpr std::string_view kRingType = "uint16";

std::string ply_header(const PointCloud& cloud, PlyEncoding encoding, std::string_view comment) {
  std::string header = "ply\n";
  header += encoding == PlyEncoding::ascii ? "format ascii 1.0\n" : "format binary_little_endian 1.0\n";
  header += "comment ";
  header += comment;
  header += '\n';
  // PCL's convention for an organised cloud (its PLY writer and reader): the grid's size as
  // obj_info lines; readers that do not know them skip obj_info.
  if (const std::optional<OrganisedSize> organised = cloud.organised()) {
    header += "obj_info num_cols ";
    detail::append_uint_text(header, organised->width);
    header += "\nobj_info num_rows ";
    detail::append_uint_text(header, organised->height);
    header += '\n';
  }
  header += "element vertex ";
  detail::append_uint_text(header, cloud.size());
  header += '\n';
  for (const detail::FieldDeclaration& field : detail::written_fields(cloud.channels())) {
    header += "property ";
    header += field.is_ring ? kRingType : std::string_view("float");
    (header += ' ') += field.name;
    header += '\n';
  }
  header += "end_header\n";
  return header;
}

std::optional<ScalarType> ply_scalar_type(std::string_view name) {
  if (name == "char" || name == "int8") return ScalarType::i8;
  if (name == "uchar" || name == "uint8") return ScalarType::u8;
  if (name == "short" || name == "int16") return ScalarType::i16;
  if (name == "ushort" || name == "uint16") return ScalarType::u16;
  if (name == "int" || name == "int32") return ScalarType::i32;
  if (name == "uint" || name == "uint32") return ScalarType::u32;
  if (name == "float" || name == "float32") return ScalarType::f32;
  if (name == "double" || name == "float64") return ScalarType::f64;
  return std::nullopt;
}

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<FieldSpec> properties;
  bool has_list = false;
};

struct PlyHeader {
  PlyEncoding encoding = PlyEncoding::ascii;
  std::optional<std::uint64_t> columns;  // obj_info num_cols / num_rows (PCL's organised size)
  std::optional<std::uint64_t> rows;
  std::vector<PlyElement> elements;
  std::size_t body_offset = 0;
};

Expected<PlyEncoding, CloudIoError> parse_format_line(std::string_view line) {
  detail::TokenCursor tokens(line);
  if (tokens.next() != std::optional<std::string_view>("format")) {
    return Unexpected(CloudIoError::malformed_header);
  }
  const std::optional<std::string_view> format = tokens.next();
  const std::optional<std::string_view> version = tokens.next();
  if (!format || version != std::optional<std::string_view>("1.0") || tokens.next()) {
    return Unexpected(CloudIoError::malformed_header);
  }
  if (*format == "ascii") return PlyEncoding::ascii;
  if (*format == "binary_little_endian") return PlyEncoding::binary_little_endian;
  if (*format == "binary_big_endian") return Unexpected(CloudIoError::unsupported_layout);
  return Unexpected(CloudIoError::malformed_header);
}

// One "element" or "property" line added to the header being built.
std::optional<CloudIoError> parse_declaration(std::string_view keyword, detail::TokenCursor& tokens,
                                              PlyHeader& header) {
  if (keyword == "element") {
    const std::optional<std::string_view> name = tokens.next();
    const std::optional<std::string_view> count_text = tokens.next();
    if (!name || !count_text || tokens.next()) return CloudIoError::malformed_header;
    const std::optional<std::uint64_t> count = detail::parse_unsigned(*count_text);
    if (!count) return CloudIoError::malformed_header;
    header.elements.push_back(PlyElement{std::string(*name), *count, {}, false});
    return std::nullopt;
  }
  // keyword == "property"
  if (header.elements.empty()) return CloudIoError::malformed_header;
  const std::optional<std::string_view> type_name = tokens.next();
  if (!type_name) return CloudIoError::malformed_header;
  if (*type_name == "list") {
    header.elements.back().has_list = true;
    return std::nullopt;
  }
  const std::optional<ScalarType> type = ply_scalar_type(*type_name);
  const std::optional<std::string_view> name = tokens.next();
  if (!type || !name || tokens.next()) return CloudIoError::malformed_header;
  header.elements.back().properties.push_back(FieldSpec{std::string(*name), *type, 1});
  return std::nullopt;
}

Expected<PlyHeader, CloudIoError> parse_ply_header(std::string_view file_bytes) {
  detail::LineCursor lines(file_bytes);
  if (lines.next_line() != std::optional<std::string_view>("ply")) {
    return Unexpected(CloudIoError::bad_magic);
  }
  const std::optional<std::string_view> format_line = lines.next_line();
  if (!format_line) return Unexpected(CloudIoError::truncated_data);
  const Expected<PlyEncoding, CloudIoError> encoding = parse_format_line(*format_line);
  if (!encoding) return Unexpected(encoding.error());

  PlyHeader header;
  header.encoding = *encoding;
  while (true) {
    const std::optional<std::string_view> line = lines.next_line();
    if (!line) return Unexpected(CloudIoError::truncated_data);  // no end_header
    detail::TokenCursor tokens(*line);
    const std::optional<std::string_view> keyword = tokens.next();
    if (!keyword) return Unexpected(CloudIoError::malformed_header);
    if (*keyword == "comment") continue;
    if (*keyword == "obj_info") {
      const std::optional<std::string_view> key = tokens.next();
      const std::optional<std::string_view> value = tokens.next();
      const std::optional<std::uint64_t> number = value ? detail::parse_unsigned(*value) : std::nullopt;
      if (key == std::optional<std::string_view>("num_cols")) header.columns = number;
      if (key == std::optional<std::string_view>("num_rows")) header.rows = number;
      continue;
    }
    if (*keyword == "end_header") {
      if (tokens.next()) return Unexpected(CloudIoError::malformed_header);
      break;
    }
    if (*keyword != "element" && *keyword != "property") {
      return Unexpected(CloudIoError::malformed_header);
    }
    if (const std::optional<CloudIoError> error = parse_declaration(*keyword, tokens, header)) {
      return Unexpected(*error);
    }
  }
  header.body_offset = lines.offset();
  return header;
}

// Skips the data of an element that precedes "vertex"; returns the remaining body.
Expected<std::string_view, CloudIoError> skip_element(std::string_view body, const PlyElement& element,
                                                      PlyEncoding encoding) {
  if (element.has_list) return Unexpected(CloudIoError::unsupported_layout);
  if (encoding == PlyEncoding::ascii) {
    detail::LineCursor lines(body);
    for (std::uint64_t row = 0; row < element.count; ++row) {
      if (!lines.next_line()) return Unexpected(CloudIoError::truncated_data);
    }
    return body.substr(lines.offset());
  }
  std::size_t record_size = 0;
  for (const FieldSpec& property : element.properties) record_size += detail::scalar_size(property.type);
  if (record_size != 0 && element.count > body.size() / record_size) {
    return Unexpected(CloudIoError::truncated_data);
  }
  return body.substr(static_cast<std::size_t>(element.count) * record_size);
}

}  // namespace

Expected<std::string, CloudIoError> encode_ply(const PointCloud& cloud, PlyEncoding encoding,
                                               std::string_view comment) {
  if (cloud.size() > std::numeric_limits<std::uint32_t>::max()) {
    return Unexpected(CloudIoError::too_many_points);
  }
  if (comment.find_first_of("\r\n") != std::string_view::npos) {
    return Unexpected(CloudIoError::bad_comment);
  }
  std::string file = ply_header(cloud, encoding, comment);
  if (encoding == PlyEncoding::ascii) {
    detail::append_ascii_records(file, cloud);
  } else {
    detail::append_binary_records(file, cloud);
  }
  return file;
}

Expected<PointCloud, CloudIoError> decode_ply(std::string_view file_bytes) {
  const Expected<PlyHeader, CloudIoError> header = parse_ply_header(file_bytes);
  if (!header) return Unexpected(header.error());
  std::string_view body = file_bytes.substr(header->body_offset);
  for (const PlyElement& element : header->elements) {
    if (element.name != "vertex") {
      const Expected<std::string_view, CloudIoError> rest = skip_element(body, element, header->encoding);
      if (!rest) return Unexpected(rest.error());
      body = *rest;
      continue;
    }
    if (element.has_list) return Unexpected(CloudIoError::unsupported_layout);
    Expected<PointCloud, CloudIoError> cloud =
        header->encoding == PlyEncoding::ascii ? detail::read_ascii_records(body, element.properties, element.count)
                                               : detail::read_binary_records(body, element.properties, element.count);
    // An organised size that does not match the count is ignored, as PCL does with a grid of one
    // row: the points are still all there.
    if (cloud && header->columns && header->rows && *header->rows > 1 &&
        *header->columns <= std::numeric_limits<std::uint32_t>::max() &&
        *header->rows <= std::numeric_limits<std::uint32_t>::max()) {
      (void)cloud->set_organised(OrganisedSize{static_cast<std::uint32_t>(*header->columns),
                                               static_cast<std::uint32_t>(*header->rows)});
    }
    return cloud;
  }
  return Unexpected(CloudIoError::missing_field);
}

}  // namespace ldoem::cloud
