// libFuzzer target: the PLY and PCD readers (driver/cloud). The first input byte picks the
// reader (PLY, PCD, or by magic like read_cloud_file); the rest is the file. A cloud either
// reader accepts must encode again (in the same family) and decode to the same point count.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "ldoem/cloud/cloud_file.hpp"
#include "ldoem/cloud/pcd.hpp"
#include "ldoem/cloud/ply.hpp"

namespace cl = ldoem::cloud;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  auto cloud = data[0] % 3 == 0   ? cl::decode_ply(bytes)
               : data[0] % 3 == 1 ? cl::decode_pcd(bytes)
                                  : cl::decode_cloud(bytes);
  if (!cloud) return 0;
  const auto format = data[0] % 3 == 1 ? cl::CloudFileFormat::pcd_binary : cl::CloudFileFormat::ply_binary;
  const auto encoded = cl::encode_cloud(*cloud, format);
  if (!encoded) return 0;  // e.g. a comment the writer refuses; the reader was lenient
  const auto decoded = cl::decode_cloud(*encoded);
  if (!decoded || decoded->size() != cloud->size()) std::abort();
  return 0;
}
