// The vertex records PLY and PCD share: x y z, then intensity and ring when the cloud has them,
// in the order both headers declare them (ply.cpp, pcd.cpp).
#include "record_writer.hpp"

#include "codec_support.hpp"

namespace ldoem::cloud::detail {

void append_ascii_records(std::string& out, const PointCloud& cloud) {
  for (std::size_t index = 0; index < cloud.size(); ++index) {
    const PointRecord record = cloud.record(index);
    append_float_text(out, record.position.x_m);
    out += ' ';
    append_float_text(out, record.position.y_m);
    out += ' ';
    append_float_text(out, record.position.z_m);
    if (cloud.channels().intensity) {
      out += ' ';
      append_float_text(out, record.intensity);
    }
    if (cloud.channels().ring) {
      out += ' ';
      append_uint_text(out, record.ring);
    }
    out += '\n';
  }
}

void append_binary_records(std::string& out, const PointCloud& cloud) {
  for (std::size_t index = 0; index < cloud.size(); ++index) {
    const PointRecord record = cloud.record(index);
    append_float_le(out, record.position.x_m);
    append_float_le(out, record.position.y_m);
    append_float_le(out, record.position.z_m);
    if (cloud.channels().intensity) detail::append_float_le(out, record.intensity);
    if (cloud.channels().ring) detail::append_uint_le(out, record.ring);
  }
}

}  // namespace ldoem::cloud::detail
