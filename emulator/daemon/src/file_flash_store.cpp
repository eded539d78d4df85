#include "ldoem/daemon/file_flash_store.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <system_error>

namespace ldoem::daemon {

protocol::Bytes FileFlashStore::load() const {
  std::ifstream in(path_, std::ios::binary);
  if (!in) {
    return {};
  }
  return protocol::Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void FileFlashStore::save(protocol::ByteView image) {
  std::filesystem::path temporary = path_;
  temporary += ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(image.data()), static_cast<std::streamsize>(image.size()));
    out.flush();
    if (!out) {
      last_error_ = "write " + temporary.string() + ": " + std::strerror(errno);
      return;
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path_, error);
  if (error) {
    last_error_ = "rename " + path_.string() + ": " + error.message();
    return;
  }
  last_error_.clear();
}

}  // namespace ldoem::daemon
