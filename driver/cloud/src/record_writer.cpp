// The vertex records PLY and PCD share: x y z, then intensity, t range azimuth tilt and ring
// when the cloud has them, in the order both headers declare them (ply.cpp, pcd.cpp).
#include "record_writer.hpp"

#include "codec_support.hpp"

namespace ldoem::cloud::detail {
namespace {

// The float fields of one record after x y z, in file order.
int float_fields(const PointRecord& record, const CloudChannels& channels, std::array<float, 8>& out) {
  int count = 0;
  out[count++] = record.position.x_m;
  out[count++] = record.position.y_m;
  out[count++] = record.position.z_m;
  if (channels.intensity) out[count++] = record.intensity;
  if (channels.beam) {
    out[count++] = record.time_s;
    out[count++] = record.range_m;
    out[count++] = record.azimuth_rad;
    out[count++] = record.tilt_rad;
  }
  return count;
}

}  // namespace

std::vector<FieldDeclaration> written_fields(const CloudChannels& channels) {
  std::vector<FieldDeclaration> fields{{"x", false}, {"y", false}, {"z", false}};
  if (channels.intensity) fields.push_back({"intensity", false});
  if (channels.beam) {
    for (const char* name : {"t", "range", "azimuth", "tilt"}) fields.push_back({name, false});
  }
  if (channels.ring) fields.push_back({"ring", true});
  return fields;
}

void append_ascii_records(std::string& out, const PointCloud& cloud) {
  std::array<float, 8> values{};
  for (std::size_t index = 0; index < cloud.size(); ++index) {
    const PointRecord record = cloud.record(index);
    const int count = float_fields(record, cloud.channels(), values);
    for (int i = 0; i < count; ++i) {
      if (i > 0) out += ' ';
      append_float_text(out, values[static_cast<std::size_t>(i)]);
    }
    if (cloud.channels().ring) {
      out += ' ';
      append_uint_text(out, record.ring);
    }
    out += '\n';
  }
}

void append_binary_records(std::string& out, const PointCloud& cloud) {
  std::array<float, 8> values{};
  for (std::size_t index = 0; index < cloud.size(); ++index) {
    const PointRecord record = cloud.record(index);
    const int count = float_fields(record, cloud.channels(), values);
    for (int i = 0; i < count; ++i) append_float_le(out, values[static_cast<std::size_t>(i)]);
    if (cloud.channels().ring) detail::append_uint_le(out, record.ring);
  }
}

}  // namespace ldoem::cloud::detail
