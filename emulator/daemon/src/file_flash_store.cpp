#include "ldoem/daemon/file_flash_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace ldoem::daemon {

base::Expected<protocol::Bytes, std::string> FileFlashStore::read() const {
  const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return protocol::Bytes{};  // never saved: the scene's defaults (D4)
    return base::Unexpected("cannot open: " + std::string(std::strerror(errno)));
  }
  protocol::Bytes image;
  std::uint8_t buffer[4096];
  for (;;) {
    const ssize_t got = ::read(fd, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      const std::string why = std::strerror(errno);
      ::close(fd);
      return base::Unexpected("cannot read: " + why);
    }
    if (got == 0) break;
    // A flash image is a few hundred bytes; a huge file is not one (and must not fill memory).
    if (image.size() + static_cast<std::size_t>(got) > kMaxImageBytes) {
      ::close(fd);
      return base::Unexpected("larger than " + std::to_string(kMaxImageBytes) + " bytes: not a flash image");
    }
    image.insert(image.end(), buffer, buffer + got);
  }
  ::close(fd);
  return image;
}

protocol::Bytes FileFlashStore::load() const {
  auto image = read();
  return image ? std::move(*image) : protocol::Bytes{};
}

// mkstemp in the flash file's folder (O_EXCL: a symlink planted at a predictable name is never
// followed), write, fsync, rename over the image, fsync the folder: after save() returns the new
// image survives a power cut, and a crash at any point leaves the old image or the new one.
bool FileFlashStore::save(protocol::ByteView image) {
  // "flash /srv/cell.flash not saved: mkstemp: No such file or directory"
  const auto failed = [this](const char* step, int error) {
    last_error_ = "flash " + path_.string() + " not saved: " + step + ": " + std::strerror(error);
    return false;
  };
  const std::filesystem::path folder = path_.has_parent_path() ? path_.parent_path() : std::filesystem::path(".");
  std::string temporary = (folder / ("." + path_.filename().string() + ".XXXXXX")).string();
  const int fd = ::mkstemp(temporary.data());
  if (fd < 0) return failed("mkstemp", errno);
  const auto abandon = [&](const char* step) {
    const int error = errno;
    ::close(fd);
    ::unlink(temporary.c_str());
    return failed(step, error);
  };
  for (std::size_t done = 0; done < image.size();) {
    const ssize_t written = ::write(fd, image.data() + done, image.size() - done);
    if (written < 0 && errno == EINTR) continue;
    if (written < 0) return abandon("write");
    done += static_cast<std::size_t>(written);
  }
  if (::fchmod(fd, 0644) != 0) return abandon("fchmod");
  if (::fsync(fd) != 0) return abandon("fsync");
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    return failed("close", error);
  }
  if (::rename(temporary.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary.c_str());
    return failed("rename", error);
  }
  const int folder_fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (folder_fd < 0) return failed("open the folder to fsync it", errno);
  if (::fsync(folder_fd) != 0) {
    const int error = errno;
    ::close(folder_fd);
    return failed("fsync the folder", error);
  }
  ::close(folder_fd);
  last_error_.clear();
  return true;
}

}  // namespace ldoem::daemon
