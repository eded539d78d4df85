#include "ldoem/daemon/file_flash_store.hpp"

#include "ldoem/base/regular_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace ldoem::daemon {
namespace {

constexpr int kMaxSymlinkHops = 40;  // as the kernel's ELOOP limit

// Issue 27 (D12): save() renames a new file over the flash; over a symlink that would replace
// the link and leave its target stale. Resolving the links first writes through them.
std::filesystem::path resolve_links(std::filesystem::path path) {
  std::error_code error;
  for (int hop = 0; hop < kMaxSymlinkHops && std::filesystem::is_symlink(path, error); ++hop) {
    const std::filesystem::path target = std::filesystem::read_symlink(path, error);
    if (error) break;
    path = target.is_absolute() ? target : path.parent_path() / target;
  }
  return path;
}

// mkstemp's names: "." + the flash's file name + "." + six characters of [A-Za-z0-9].
bool is_temporary_of(std::string_view name, std::string_view flash_name) {
  constexpr std::size_t kSuffix = 7;  // ".XXXXXX"
  if (name.size() != 1 + flash_name.size() + kSuffix || name[0] != '.') return false;
  if (name.substr(1, flash_name.size()) != flash_name || name[1 + flash_name.size()] != '.') return false;
  for (const char c : name.substr(name.size() - 6)) {
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'))) return false;
  }
  return true;
}

}  // namespace

FileFlashStore::FileFlashStore(std::filesystem::path path) : path_(resolve_links(std::move(path))) {}

std::optional<std::string> FileFlashStore::remove_stale_temporaries() const {
  const std::filesystem::path folder = path_.has_parent_path() ? path_.parent_path() : std::filesystem::path(".");
  const std::string flash_name = path_.filename().string();
  DIR* listing = ::opendir(folder.c_str());
  if (listing == nullptr) return std::nullopt;
  std::size_t removed = 0;
  while (const dirent* entry = ::readdir(listing)) {
    if (!is_temporary_of(entry->d_name, flash_name)) continue;
    struct stat info {};
    // Only regular files: whatever else wears the name is not ours.
    if (::fstatat(::dirfd(listing), entry->d_name, &info, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(info.st_mode)) continue;
    if (::unlinkat(::dirfd(listing), entry->d_name, 0) == 0) ++removed;
  }
  ::closedir(listing);
  if (removed == 0) return std::nullopt;
  return "flash " + path_.string() + ": removed " + std::to_string(removed) + " temporary file(s) of a save that was killed";
}

base::Expected<protocol::Bytes, std::string> FileFlashStore::read() const {
  // Issue 27 (D11): O_NONBLOCK and fstat first, so a FIFO is refused at once, not waited on.
  auto opened = base::open_regular_file(path_, O_RDONLY);
  if (!opened) {
    if (opened.error().error_number == ENOENT) return protocol::Bytes{};  // never saved: the scene's defaults (D4)
    return base::Unexpected(opened.error().text);
  }
  const int fd = opened->release();
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
  // D12: a file that exists is a saved image; an empty one was truncated or made by hand, and
  // running on the defaults would overwrite it without a word.
  if (image.empty()) return base::Unexpected(std::string("is empty (0 bytes): not a flash image"));
  return image;
}

protocol::Bytes FileFlashStore::load() const {
  auto image = read();
  return image ? std::move(*image) : protocol::Bytes{};
}

// mkstemp in the flash file's folder (O_EXCL: a symlink planted at a predictable name is never
// followed), write, fsync, rename over the image, fsync the folder: after save() returns the new
// image survives a power cut, and a crash at any point leaves the old image or the new one.
control::FlashStore::Saved FileFlashStore::save(protocol::ByteView image) {
  // "flash /srv/cell.flash not saved: mkstemp: No such file or directory"
  const auto failed = [this](const char* step, int error) -> Saved {
    return base::Unexpected("flash " + path_.string() + " not saved: " + step + ": " + std::strerror(error));
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
  return std::monostate{};
}

}  // namespace ldoem::daemon
