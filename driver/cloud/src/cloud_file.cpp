#include "ldoem/cloud/cloud_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <iterator>

#include "ldoem/cloud/pcd.hpp"
#include "ldoem/cloud/ply.hpp"

namespace ldoem::cloud {

std::string_view to_string(CloudIoError error) {
  switch (error) {
    case CloudIoError::too_many_points: return "too_many_points";
    case CloudIoError::bad_comment: return "bad_comment";
    case CloudIoError::bad_magic: return "bad_magic";
    case CloudIoError::malformed_header: return "malformed_header";
    case CloudIoError::unsupported_layout: return "unsupported_layout";
    case CloudIoError::missing_field: return "missing_field";
    case CloudIoError::inconsistent_header: return "inconsistent_header";
    case CloudIoError::truncated_data: return "truncated_data";
    case CloudIoError::malformed_number: return "malformed_number";
    case CloudIoError::cannot_open_file: return "cannot_open_file";
    case CloudIoError::io_failed: return "io_failed";
  }
  return "unknown";
}

std::string_view to_string(CloudFileFormat format) {
  switch (format) {
    case CloudFileFormat::ply_ascii: return "ply-ascii";
    case CloudFileFormat::ply_binary: return "ply-binary";
    case CloudFileFormat::pcd_ascii: return "pcd-ascii";
    case CloudFileFormat::pcd_binary: return "pcd-binary";
  }
  return "unknown";
}

std::optional<CloudFileFormat> parse_cloud_file_format(std::string_view text) {
  for (CloudFileFormat format : {CloudFileFormat::ply_ascii, CloudFileFormat::ply_binary,
                                 CloudFileFormat::pcd_ascii, CloudFileFormat::pcd_binary}) {
    if (text == to_string(format)) return format;
  }
  return std::nullopt;
}

Expected<std::string, CloudIoError> encode_cloud(const PointCloud& cloud, CloudFileFormat format) {
  switch (format) {
    case CloudFileFormat::ply_ascii: return encode_ply(cloud, PlyEncoding::ascii);
    case CloudFileFormat::ply_binary: return encode_ply(cloud, PlyEncoding::binary_little_endian);
    case CloudFileFormat::pcd_ascii: return encode_pcd(cloud, PcdEncoding::ascii);
    case CloudFileFormat::pcd_binary: return encode_pcd(cloud, PcdEncoding::binary);
  }
  return Unexpected(CloudIoError::unsupported_layout);
}

Expected<PointCloud, CloudIoError> decode_cloud(std::string_view file_bytes) {
  const bool is_ply = file_bytes.starts_with("ply\n") || file_bytes.starts_with("ply\r\n");
  return is_ply ? decode_ply(file_bytes) : decode_pcd(file_bytes);
}

namespace {

bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t written = ::write(fd, bytes.data(), bytes.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes.remove_prefix(static_cast<std::size_t>(written));
  }
  return true;
}

}  // namespace

// A temporary file in the target's folder (same file system, so the rename is atomic), written,
// flushed to disk, then renamed over the target and the folder flushed: a reader sees the old
// file or the whole new one, never a truncated one, and a crash loses no data already reported
// as written. mkstemp opens with O_EXCL, so no symlink planted at the temporary name is followed.
Expected<std::size_t, CloudIoError> write_file_bytes(const std::filesystem::path& path,
                                                     std::string_view bytes) {
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::string temporary = (folder / ("." + path.filename().string() + ".XXXXXX")).string();
  const int fd = ::mkstemp(temporary.data());
  if (fd < 0) return Unexpected(CloudIoError::cannot_open_file);
  const bool written = write_all(fd, bytes) && ::fchmod(fd, 0644) == 0 && ::fsync(fd) == 0;
  if (::close(fd) != 0 || !written || ::rename(temporary.c_str(), path.c_str()) != 0) {
    ::unlink(temporary.c_str());
    return Unexpected(CloudIoError::io_failed);
  }
  if (const int folder_fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); folder_fd >= 0) {
    const bool synced = ::fsync(folder_fd) == 0;
    ::close(folder_fd);
    if (!synced) return Unexpected(CloudIoError::io_failed);
  }
  return bytes.size();
}

Expected<std::string, CloudIoError> read_file_bytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Unexpected(CloudIoError::cannot_open_file);
  std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) return Unexpected(CloudIoError::io_failed);
  return bytes;
}

Expected<std::size_t, CloudIoError> write_cloud_file(const std::filesystem::path& path,
                                                     const PointCloud& cloud, CloudFileFormat format) {
  const Expected<std::string, CloudIoError> bytes = encode_cloud(cloud, format);
  if (!bytes) return Unexpected(bytes.error());
  return write_file_bytes(path, *bytes);
}

Expected<PointCloud, CloudIoError> read_cloud_file(const std::filesystem::path& path) {
  const Expected<std::string, CloudIoError> bytes = read_file_bytes(path);
  if (!bytes) return Unexpected(bytes.error());
  return decode_cloud(*bytes);
}

}  // namespace ldoem::cloud
