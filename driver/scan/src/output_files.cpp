#include "ldoem/scan/output_files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ldoem::scan {

namespace {

std::filesystem::path folder_of(const std::filesystem::path& path) {
  return path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
}

std::string os_error(int error_number) { return std::strerror(error_number); }

// A new file beside PATH that no one else can have opened (mkstemp: O_EXCL, mode 0600).
struct Temporary {
  std::string name;
  int fd = -1;
};

base::Expected<Temporary, int> make_temporary(const std::filesystem::path& path) {
  Temporary temporary{(folder_of(path) / ("." + path.filename().string() + ".XXXXXX")).string(), -1};
  temporary.fd = ::mkstemp(temporary.name.data());
  if (temporary.fd < 0) {
    return base::Unexpected(errno);
  }
  return temporary;
}

bool write_whole(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

}  // namespace

base::Expected<std::monostate, std::string> check_output_path(const std::filesystem::path& path) {
  const std::filesystem::path folder = folder_of(path);
  struct stat info {};
  if (::stat(folder.c_str(), &info) != 0) {
    return base::Unexpected(path.string() + ": folder " + folder.string() + ": " + os_error(errno));
  }
  if (!S_ISDIR(info.st_mode)) {
    return base::Unexpected(path.string() + ": " + folder.string() + " is not a folder");
  }
  if (::stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
    return base::Unexpected(path.string() + ": is a folder");
  }
  auto temporary = make_temporary(path);
  if (!temporary) {
    return base::Unexpected(path.string() + ": cannot create a file in " + folder.string() + ": " +
                            os_error(temporary.error()));
  }
  ::close(temporary->fd);
  ::unlink(temporary->name.c_str());
  return std::monostate{};
}

base::Expected<std::monostate, std::string> write_all_or_none(const std::vector<OutputFile>& files) {
  std::vector<std::string> written;
  const auto discard = [&written] {
    for (const std::string& name : written) ::unlink(name.c_str());
  };
  for (const OutputFile& file : files) {
    auto temporary = make_temporary(file.path);
    if (!temporary) {
      discard();
      return base::Unexpected("write " + file.path.string() + ": " + os_error(temporary.error()));
    }
    written.push_back(temporary->name);
    int error_number = 0;
    if (!write_whole(temporary->fd, file.bytes) || ::fchmod(temporary->fd, 0644) != 0 || ::fsync(temporary->fd) != 0) {
      error_number = errno;
    }
    if (::close(temporary->fd) != 0 && error_number == 0) error_number = errno;
    if (error_number != 0) {
      discard();
      return base::Unexpected("write " + file.path.string() + ": " + os_error(error_number));
    }
  }
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (::rename(written[i].c_str(), files[i].path.c_str()) != 0) {
      const int error_number = errno;
      // Those renamed already stay (they are whole files); the rest are removed.
      for (std::size_t j = i; j < written.size(); ++j) ::unlink(written[j].c_str());
      return base::Unexpected("rename into " + files[i].path.string() + ": " + os_error(error_number));
    }
  }
  return std::monostate{};
}

}  // namespace ldoem::scan
