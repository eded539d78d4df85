#include "ldoem/daemon/file_flash_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

namespace ldoem::daemon {

protocol::Bytes FileFlashStore::load() const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) {
    return {};
  }
  return protocol::Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// mkstemp in the flash file's folder (O_EXCL: a symlink planted at a predictable name is never
// followed), write, fsync, rename over the image, fsync the folder: after save() returns the new
// image survives a power cut, and a crash at any point leaves the old image or the new one.
void FileFlashStore::save(protocol::ByteView image) {
  const std::filesystem::path folder = path_.has_parent_path() ? path_.parent_path() : std::filesystem::path(".");
  std::string temporary = (folder / ("." + path_.filename().string() + ".XXXXXX")).string();
  const int fd = ::mkstemp(temporary.data());
  if (fd < 0) {
    last_error_ = "mkstemp " + temporary + ": " + std::strerror(errno);
    return;
  }
  const auto fail = [&](const char* operation) {
    last_error_ = std::string(operation) + " " + temporary + ": " + std::strerror(errno);
    ::close(fd);
    ::unlink(temporary.c_str());
  };
  for (std::size_t done = 0; done < image.size();) {
    const ssize_t written = ::write(fd, image.data() + done, image.size() - done);
    if (written < 0 && errno == EINTR) continue;
    if (written < 0) return fail("write");
    done += static_cast<std::size_t>(written);
  }
  if (::fchmod(fd, 0644) != 0) return fail("fchmod");
  if (::fsync(fd) != 0) return fail("fsync");
  if (::close(fd) != 0) {
    last_error_ = "close " + temporary + ": " + std::strerror(errno);
    ::unlink(temporary.c_str());
    return;
  }
  if (::rename(temporary.c_str(), path_.c_str()) != 0) {
    last_error_ = "rename " + path_.string() + ": " + std::strerror(errno);
    ::unlink(temporary.c_str());
    return;
  }
  const int folder_fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (folder_fd < 0 || ::fsync(folder_fd) != 0) {
    last_error_ = "fsync " + folder.string() + ": " + std::strerror(errno);
    if (folder_fd >= 0) ::close(folder_fd);
    return;
  }
  ::close(folder_fd);
  last_error_.clear();
}

}  // namespace ldoem::daemon
